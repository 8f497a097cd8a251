#pragma once
// Find the teacher and follow the face (the paper's §6.4), from perception alone: the flight software
// is told nothing of where the teacher walks, where they pause or how fast they go; the lab tells it
// the room, the benches and instruments, and the platform. Three stages:
//  1 take off, climb to a standing adult's face height, the scale manoeuvre (SLAM's map gets its
//    metric scale, as in inspect's stage 1, so SLAM can drive the pose while the face is only the
//    target);
//  2 search: a full yaw sweep where the drone is, then at each viewpoint over the free floor
//    (face_search_viewpoints.hpp), nearest first, until a face is tracked;
//  3 follow: hold face_distance_m in front of the face, the face centred, the line of sight aligned
//    with the teacher's heading (TeacherTrack: the walking direction while walking forwards, else
//    where the face looks; the walk's velocity measured from the faces), following the teacher's
//    motion and turns; the standoff is kept inside the geofence and reached around the teacher, never
//    through them. A face lost for a few frames is bridged along the track; longer: coast along the
//    track's motion (the teacher walked or turned out of the detector's reach), then go round the
//    place where it was lost, in the way they were turning, looking at it (a teacher who turned away
//    faces the drone again once it is in front of them), then search again from there.
// Ends on stop_face_follow (the drone hovers where it is) or when the search times out.
#include <optional>
#include <vector>

#include "control/estimate_correction.hpp"
#include "control/head_range.hpp"
#include "control/home_landing.hpp"
#include "control/mission.hpp"
#include "control/take_off_and_scale.hpp"
#include "control/teacher_track.hpp"

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
  enum class Step { Init, Sweep, Reposition, Follow, Lost, Done };
  void enter(Step step, Seconds t) {
    step_ = step;
    since_ = t;
    fresh_ = true;
  }
  // `after_loss`: the teacher was lost near the drone a moment ago; its first sweep is flown over
  // their head.
  void start_search(MissionContext& ctx, bool after_loss);
  void sweep(MissionContext& ctx);
  // The search's viewpoints over the floor the follow's fence allows now (face_search_viewpoints).
  std::vector<Eigen::Vector3d> search_viewpoints(const MissionContext& ctx) const;
  // A search tour planned while the estimate was unsure is planned again over the floor its firmer
  // estimate allows.
  void replan_search_if_roomier(const MissionContext& ctx);
  void reposition(MissionContext& ctx);
  bool face_seen(const MissionContext& ctx) const;
  void follow(MissionContext& ctx);
  void bridge_brief_loss(MissionContext& ctx);
  void lost(MissionContext& ctx);
  double go_round_sign(const MissionContext& ctx) const;
  // The geofence inset by clearance_m more; the follow's soft fence (the walls' clearance and the
  // estimate's uncertainty); that uncertainty as a clearance.
  Geofence inset_fence(const MissionContext& ctx, const Eigen::Vector3d& clearance_m) const;
  Geofence roomy_fence(const MissionContext& ctx) const;
  Eigen::Vector3d uncertainty_clearance(const MissionContext& ctx) const;
  // The set point's height: the face's (a seen face), face_blind_altitude_m (blind: the face is not
  // seen), or over_head_altitude (a head followed without its face).
  enum class StandoffAltitude { Face, Blind, OverHead };
  // Stand face_distance_m (+ beyond_m) in front of the track's place, as seen facing `heading`
  // (turning at `heading_rate`), the camera on the place, at `altitude`. `seen_face`: a place a face
  // was just seen at; the walls are no nearer the set point than to it where the estimate's
  // uncertainty would keep it farther (widened_to_face).
  void fly_standoff(MissionContext& ctx, bool new_waypoint, double heading, double heading_rate, double beyond_m,
                    StandoffAltitude altitude, const std::optional<Eigen::Vector3d>& seen_face = std::nullopt);
  double blind_altitude(const MissionContext& ctx) const;
  // Over a followed head at `head` and low enough that it stays in the image from where the drone is,
  // never above the blind altitude.
  double over_head_altitude(const MissionContext& ctx, const Eigen::Vector3d& head) const;
  void follow_estimate_corrections(const MissionContext& ctx);
  std::string describe(Seconds t) const;

  Step step_ = Step::Init;
  Seconds since_ = 0;
  Seconds search_started_ = -1;
  bool fresh_ = true;
  bool stop_requested_ = false;
  double sweep_start_yaw_ = 0;
  bool sweep_blind_ = false;  // this sweep at face_blind_altitude_m, not face height
  std::vector<Eigen::Vector3d> viewpoints_;  // the search's tour, from where it started
  std::size_t viewpoint_ = 0;                // the next one flown to
  TakeOffAndScale init_;
  Seconds last_tick_ = 0;
  EstimateCorrection estimate_correction_;  // the estimate's corrections are not the teacher's walk
  Seconds last_face_t_ = -1;
  Seconds last_posed_t_ = -1;  // the last face with its pose (not a followed head)
  TeacherTrack track_;
  HeadRange head_range_;  // a followed head's distance from the teacher's face height
  // Going round a lost face: from this heading of the track, this way (+1 counter-clockwise).
  double round_from_heading_ = 0;
  double round_sign_ = 1;
  std::string stage_text_ = "1 init: taking off";
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
