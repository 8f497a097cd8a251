#pragma once
// Find the teacher and follow the face (the paper's §6.4):
//  1 take off, climb to face height, the scale manoeuvre (SLAM's map gets its metric scale, as in
//    inspect's stage 1, so SLAM can drive the pose while the face is only the target);
//  2 search: when the lab knows the teacher's route, wait at the watch points along it
//    (teacher_watch_points.hpp: beyond each leg's end, facing the oncoming teacher) for one round of
//    the route each; otherwise a full yaw sweep, then the next viewpoint (room centre, then the room's
//    quarters); until a face is tracked;
//  3 follow: hold face_distance_m in front of the face, the face centred, the line of sight aligned with
//    the teacher's heading (TeacherTrack: the walking direction while walking forwards, else where
//    the face looks), following the teacher's motion and turns; the standoff is kept inside the
//    geofence and reached around the teacher, never through them; a lost face -> coast along the
//    teacher's motion, hold, then search; with a known route, a face lost at a corner of it (the
//    teacher turning away), or a teacher reaching a corner after which the route turns back towards
//    the drone (the standoff would have to swing round them) -> meet: go round, face_distance_m +
//    0.3 m from the next long leg's start, to its front, facing back along it (next_leg_meeting_point()),
//    and wait there for the teacher to turn into view along that leg.
// Ends on stop_face_follow (the drone hovers where it is) or when the search times out.
#include <vector>

#include "control/home_landing.hpp"
#include "control/mission.hpp"
#include "control/take_off_and_scale.hpp"
#include "control/teacher_track.hpp"
#include "control/teacher_watch_points.hpp"

namespace labo::control {

class FindTeacherMission final : public Mission {
 public:
  explicit FindTeacherMission(Seconds t) : since_(t) {}
  std::string name() const override { return "find_teacher"; }
  MissionOutcome step(MissionContext& ctx) override;
  int stage_index() const override;
  int stage_count() const override { return 3; }
  std::string stage() const override { return stage_text_; }
  // Following servoes on the face's pose relative to the camera: the pose estimate (SLAM, or navdata
  // odometry when SLAM is lost, drifting a few cm over a follow) only has to be locally consistent.
  // Searching looks for the face and holds on whatever source there is.
  bool needs_visual_localization() const override { return false; }
  bool accepts_stop_face_follow() const override { return true; }
  void stop_face_follow() override { stop_requested_ = true; }

 private:
  enum class Step { Init, Sweep, Reposition, Watch, Follow, Lost, Meet, Done };
  void enter(Step step, Seconds t) {
    step_ = step;
    since_ = t;
    fresh_ = true;
    corner_eta_ = -1;
  }
  std::vector<Eigen::Vector3d> viewpoints(const MissionContext& ctx) const;
  void start_search(MissionContext& ctx);
  void plan_transit(const MissionContext& ctx, const WatchPoint& to);
  bool predict_from_route(const MissionContext& ctx, double corner_radius_m);
  bool predict_from_route(const MissionContext& ctx, const std::optional<RouteLeg>& leg);
  bool predict_walk_along_leg(const MissionContext& ctx);
  void place_on_meeting_leg(const MissionContext& ctx);

  bool walk_into_corner(MissionContext& ctx);
  bool turning_back_ahead(const MissionContext& ctx);
  Geofence roomy_fence(const MissionContext& ctx) const;
  bool face_on_meeting_leg(const MissionContext& ctx) const;
  void meet(MissionContext& ctx);
  bool face_seen(const MissionContext& ctx) const;
  void follow(MissionContext& ctx);
  void fly_standoff(MissionContext& ctx, bool new_waypoint, const Eigen::Vector3d& orbit_centre);
  void fly_standoff(MissionContext& ctx, bool new_waypoint, const Eigen::Vector3d& orbit_centre, const Eigen::Vector3d& look_at,
                    const Eigen::Vector3d& look_at_velocity);
  void lost(MissionContext& ctx);
  void follow_estimate_corrections(const MissionContext& ctx);
  std::string describe(Seconds t) const;

  Step step_ = Step::Init;
  Seconds since_ = 0;
  Seconds search_started_ = -1;
  bool fresh_ = true;
  bool stop_requested_ = false;
  double sweep_start_yaw_ = 0;
  std::size_t viewpoint_ = 0;
  TakeOffAndScale init_;
  std::vector<WatchPoint> watch_points_;    // empty: the lab has no teacher route; sweep instead
  WatchPoint watch_;                        // the watch point flown to / watched from
  bool resume_track_ = false;               // the next face takes up the track's heading (after a meeting)
  Eigen::Vector3d meet_centre_ = Eigen::Vector3d::Zero();  // gone round at a meeting: the corner and the leg's start
  // The meeting's leg and where the teacher is on it: `meet_on_leg_m_` along it, walking at the route's
  // speed from `meet_walk_from_` on (infinite: standing at its start).
  RouteLeg meet_leg_;
  double meet_on_leg_m_ = 0;
  Seconds meet_walk_from_ = 0;
  // Before the meeting: still walking into the corner from `walk_in_from_` (at `walk_in_t0_`) until
  // `walk_in_until_`, followed in front as before.
  Eigen::Vector2d walk_in_from_ = Eigen::Vector2d::Zero();
  Seconds walk_in_t0_ = 0;
  Seconds walk_in_until_ = -1;
  Seconds meet_arrived_at_ = -1;  // when they reached the corner before the meeting's leg (-1: not known)
  Seconds corner_eta_ = -1;  // following into a turn-back corner: when they reach it
  // Met in front of a leg, the teacher standing at its start: their set-off is fed forward (the track
  // moves at least at the route's walking velocity along the leg) from the first sign of it in the
  // face's place, or from a little before the route's time when that is known (they were seen walking
  // into the corner), until the face shows the walk.
  bool set_off_armed_ = false;
  bool set_off_timed_ = false;
  bool set_off_from_known_ = false;
  Eigen::Vector2d set_off_from_ = Eigen::Vector2d::Zero();  // where the face stood when taken up (or an early set-off ended)
  Seconds set_off_armed_until_ = -1;
  Seconds set_off_started_ = -1;  // fed forward since (-1: not yet)
  bool set_off_by_route_ = false;      // ... started by the route's time (else by the face's first move)
  double set_off_walked_at_start_ = 0;  // how far the face had moved along the leg then
  bool set_off_confirmed_ = false;     // the face has walked on since: the walk is seen, not only expected
  // Fed forward and not yet confirmed: the track's velocity along the leg is the expectation's.
  bool set_off_unconfirmed() const { return set_off_armed_ && set_off_started_ >= 0 && !set_off_confirmed_; }
  void expect_set_off(const MissionContext& ctx);
  std::vector<PoseTarget> transit_;         // legs to it
  std::size_t transit_leg_ = 0;
  Seconds last_tick_ = 0;
  // The pose estimate at the last tick (position, velocity): its corrections are not the teacher's walk.
  bool have_last_pose_ = false;
  Eigen::Vector3d last_position_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d last_velocity_ = Eigen::Vector3d::Zero();
  Seconds last_face_t_ = -1;
  TeacherTrack track_;
  double standoff_m_ = 1.0;                 // face_distance_m, farther while meeting on the next leg
  std::string stage_text_ = "1 taking off";
};

// Return home and land from wherever the drone is: stages of HomeLanding (4 return, 5 platform,
// 6 land), numbered 1-3 here.
class ReturnHomeMission final : public Mission {
 public:
  explicit ReturnHomeMission(Seconds t, std::string why) : why_(std::move(why)) { home_.start(t); }
  std::string name() const override { return "return_home"; }
  MissionOutcome step(MissionContext& ctx) override;
  int stage_index() const override { return home_.paper_stage() - 3; }
  int stage_count() const override { return 3; }
  std::string stage() const override { return stage_text_; }
  bool needs_visual_localization() const override { return home_.paper_stage() != 6; }
  bool tolerates_dead_reckoning() const override { return home_.paper_stage() != 6; }

 private:
  HomeLanding home_;
  std::string why_;
  std::string stage_text_ = "4 return";
};

}  // namespace labo::control
