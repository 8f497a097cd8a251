#include "control/find_teacher_mission.hpp"

#include <cmath>
#include <numbers>

#include "control/face_standoff.hpp"
#include "core/frames.hpp"

namespace labo {

namespace {
constexpr double kFaceHeightM = 1.6;       // climb to about a standing teacher's face height
constexpr double kFreshObservationS = 0.3;
constexpr double kLostHoldS = 3.0;         // face lost: hold this long, then search again
constexpr double kCoastS = 0.5;            // face lost: keep following its predicted motion this long
// Face lost at a corner of the route: wait this long in front of the next long leg (in the lab of
// config/lab.json the teacher turns twice, 3 s each, around a 0.5 m leg: 7.25 s), then search.
constexpr double kMeetWaitS = 12.0;
constexpr double kMaxApproachStepM = 0.6;
// Watch points: the teacher stops this far beyond face_distance_m from the camera at a leg's end, so
// the frontal face is inside the detector's ~2.5 m range for the last metre of the leg.
constexpr double kWatchBeyondFollowM = 0.5;
// Hull (0.26 m) + the teacher's body (0.25 m) + margin: nothing is planned closer to the route.
constexpr double kRouteClearanceM = 0.8;
constexpr double kTransitAboveEyesM = 0.6;  // crossing the route: this far above the teacher's eyes
constexpr double kWatchMarginS = 5.0;       // a watch lasts one round of the route plus this
constexpr double kCornerRadiusM = 0.6;      // a face lost this near a waypoint: the teacher is turning there
constexpr double kMaxOrbitStepRad = std::numbers::pi / 3;  // the standoff's bearing leads the drone's by at most this

double bearing(const Eigen::Vector3d& from, const Eigen::Vector3d& to) { return std::atan2(to.y() - from.y(), to.x() - from.x()); }

// Does the straight flight from a to b pass within `clearance` of the teacher's route (floor plane)?
bool crosses_route(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const TeacherRoute& route, double clearance) {
  const int samples = 1 + static_cast<int>((b - a).head<2>().norm() / 0.05);
  for (int k = 0; k <= samples; ++k)
    if (distance_to_route((a + (b - a) * (static_cast<double>(k) / samples)).head<2>(), route) < clearance) return true;
  return false;
}
}  // namespace

int FindTeacherMission::stage_index() const {
  switch (step_) {
    case Step::Init: return 1;
    case Step::Sweep:
    case Step::Reposition:
    case Step::Watch: return 2;
    default: return 3;
  }
}

std::string FindTeacherMission::describe(Seconds t) const {
  switch (step_) {
    case Step::Init: return "1 " + init_.describe();
    case Step::Sweep: return "2 search: yaw sweep at viewpoint " + std::to_string(viewpoint_ + 1);
    case Step::Reposition: return "2 search: moving to viewpoint " + std::to_string(viewpoint_ + 1);
    case Step::Watch:
      return "2 search: watching the teacher's route at viewpoint " + std::to_string(viewpoint_ + 1) + " (" +
             format_seconds(t - since_) + " s)";
    case Step::Follow: return "3 face-follow";
    case Step::Lost:
      return (meeting_ ? "3 face-follow: face lost at a corner, waiting in front of the next leg (" : "3 face-follow: face lost, holding (") +
             format_seconds(t - since_) + " s)";
    case Step::Done: return "done: " + result_;
  }
  return "";
}

bool FindTeacherMission::face_seen(const MissionContext& ctx) const {
  const TargetObservation f = ctx.perception.face();
  return f.state == TrackState::Tracking && ctx.t - f.t < kFreshObservationS;
}

std::vector<Eigen::Vector3d> FindTeacherMission::viewpoints(const MissionContext& ctx) const {
  const Eigen::Vector3d lo = ctx.autopilot.fence().min(), hi = ctx.autopilot.fence().max();
  const Eigen::Vector3d c = 0.5 * (lo + hi);
  const Eigen::Vector3d q = 0.25 * (hi - lo);
  return {{c.x(), c.y(), kFaceHeightM},
          {c.x() + q.x(), c.y() + q.y(), kFaceHeightM},
          {c.x() - q.x(), c.y() + q.y(), kFaceHeightM},
          {c.x() - q.x(), c.y() - q.y(), kFaceHeightM},
          {c.x() + q.x(), c.y() - q.y(), kFaceHeightM}};
}

void FindTeacherMission::plan_transit(const MissionContext& ctx, const WatchPoint& to) {
  const Eigen::Vector3d here = ctx.pose.T_world_body.translation();
  const double yaw = ypr_from_rotation(ctx.pose.T_world_body.linear())[0];
  transit_.clear();
  transit_leg_ = 0;
  if (crosses_route(here, to.position, ctx.lab.teacher, kRouteClearanceM)) {
    // Over the teacher's head, not through them.
    const double high = std::min(ctx.lab.teacher.eye_height_m + kTransitAboveEyesM, ctx.autopilot.fence().max().z());
    transit_.push_back({{here.x(), here.y(), high}, yaw});
    transit_.push_back({{to.position.x(), to.position.y(), high}, to.yaw});
  }
  transit_.push_back({to.position, to.yaw});
}

bool FindTeacherMission::predict_from_route(const MissionContext& ctx) {
  if (watch_points_.empty()) return false;
  // The next long leg's start, the teacher facing along it (the meeting point at 0 m faces back).
  const std::optional<WatchPoint> start =
      next_leg_meeting_point(ctx.lab.teacher, track_.position().head<2>(), ctx.autopilot.fence(), 0.0, kCornerRadiusM);
  if (!start) return false;
  track_.place(start->position.head<2>(), start->yaw + std::numbers::pi);
  // Wait farther out than the follow distance: the teacher starts the leg within the detector's
  // range and walking towards the drone, and the drone, going round at this radius about the leg's
  // start, passes the teacher (within 0.6 m of it) with room to spare.
  standoff_m_ = ctx.config.mission.face_distance_m + kWatchBeyondFollowM;
  return true;
}

void FindTeacherMission::start_search(MissionContext& ctx) {
  search_started_ = ctx.t;
  watch_points_ = teacher_watch_points(ctx.lab.teacher, ctx.autopilot.fence(),
                                       ctx.config.mission.face_distance_m + kWatchBeyondFollowM, kRouteClearanceM);
  if (watch_points_.empty()) {
    enter(Step::Sweep, ctx.t);
    return;
  }
  // The nearest watch point first.
  const Eigen::Vector3d here = ctx.pose.T_world_body.translation();
  viewpoint_ = 0;
  for (std::size_t i = 1; i < watch_points_.size(); ++i)
    if ((watch_points_[i].position - here).norm() < (watch_points_[viewpoint_].position - here).norm()) viewpoint_ = i;
  watch_ = watch_points_[viewpoint_];
  plan_transit(ctx, watch_);
  enter(Step::Reposition, ctx.t);
}

void FindTeacherMission::follow(MissionContext& ctx) {
  const TargetObservation f = ctx.perception.face();
  if (f.t == last_face_t_ && !fresh_) return;  // no new face result: keep the moving set point
  const Eigen::Isometry3d T_world_face = world_pose_of(f, ctx.pose, CameraId::Front);
  if (fresh_) standoff_m_ = ctx.config.mission.face_distance_m;
  if (fresh_ || last_face_t_ < 0) track_.reset(T_world_face, f.t);
  else track_.update(T_world_face, f.t);
  last_face_t_ = f.t;
  fly_standoff(ctx, fresh_);
  fresh_ = false;
}

void FindTeacherMission::fly_standoff(MissionContext& ctx, bool new_waypoint) {
  const double d = standoff_m_;
  const Eigen::Vector3d here = ctx.pose.T_world_body.translation();
  const double a = track_.heading();
  PoseTarget next = follow_standoff(standoff_target(track_.T_world_upright_face(a), d, ctx.centre_ray_front),
                                    track_.position(), here, ctx.autopilot.fence(), kMaxOrbitStepRad);
  // Feed-forward: the standoff moves with the teacher and swings round them as they turn.
  next.velocity = track_.velocity() + d * track_.heading_rate() * Eigen::Vector3d(-std::sin(a), std::cos(a), 0.0);
  // Point the camera at the face from where the drone is (the same as the line of sight once in
  // place; it keeps a walking teacher in view while the drone catches up), with the face on the ray
  // through the image centre rather than the principal point.
  next.yaw = wrap_angle(bearing(here, track_.position()) + std::atan(ctx.centre_ray_front.x()));
  // A far standoff (the face found from 2-4 m, the teacher walking at the drone) is approached
  // through a set point at most kMaxApproachStepM ahead: a full jump saturates the tilt and the drone
  // overshoots into the teacher's face.
  const Eigen::Vector3d to_standoff = next.position - here;
  if (to_standoff.norm() > kMaxApproachStepM) next.position = here + kMaxApproachStepM * to_standoff.normalized();
  ctx.autopilot.go_to(next, ctx.t, new_waypoint);
}

void FindTeacherMission::lost(MissionContext& ctx) {
  const Seconds lost_for = ctx.t - since_;
  if (fresh_) meeting_ = false;
  if (lost_for < kCoastS) {
    // Coast along the teacher's last motion and turn (they most likely walked or turned out of view).
    track_.coast(ctx.t - last_tick_);
  } else if (!meeting_ && predict_from_route(ctx)) {
    meeting_ = true;
  }
  if (lost_for < kCoastS || meeting_) {
    fly_standoff(ctx, false);
  } else if (auto target = ctx.autopilot.target()) {
    // Hold the place, keep looking where the face went.
    const Eigen::Vector3d to_face = track_.position() - ctx.pose.T_world_body.translation();
    ctx.autopilot.go_to({target->position, std::atan2(to_face.y(), to_face.x())}, ctx.t, false);
  }
  fresh_ = false;
  if (face_seen(ctx)) enter(Step::Follow, ctx.t);
  else if (lost_for > (meeting_ ? kMeetWaitS : kLostHoldS)) start_search(ctx);
}

MissionOutcome FindTeacherMission::step(MissionContext& ctx) {
  const auto& m = ctx.config.mission;
  const Eigen::Vector3d here = ctx.pose.T_world_body.translation();
  const double yaw = ypr_from_rotation(ctx.pose.T_world_body.linear())[0];
  ctx.camera = CameraId::Front;
  ctx.focus.instrument_id.clear();
  ctx.focus.platform = false;
  ctx.focus.face = true;
  if (stop_requested_ && step_ != Step::Done) {
    ctx.autopilot.hold_here(ctx.pose, ctx.t);
    result_ = "face-follow stopped on request";
    enter(Step::Done, ctx.t);
  }
  switch (step_) {
    case Step::Init:
      // Climb to about a standing teacher's face height; SLAM gets its scale before the search.
      if (init_.step(ctx, ctx.lab.teacher.waypoints.empty() ? kFaceHeightM : ctx.lab.teacher.eye_height_m)) start_search(ctx);
      break;
    case Step::Sweep: {
      if (fresh_) sweep_start_yaw_ = ctx.autopilot.target() ? ctx.autopilot.target()->yaw : yaw;
      const double swept = m.face_search_yaw_rate * (ctx.t - since_);
      const Eigen::Vector3d hold = ctx.autopilot.target() ? ctx.autopilot.target()->position : here;
      ctx.autopilot.go_to({hold, sweep_start_yaw_ + swept}, ctx.t, fresh_);
      fresh_ = false;
      if (face_seen(ctx)) enter(Step::Follow, ctx.t);
      else if (swept >= 2 * std::numbers::pi) {
        viewpoint_ = (viewpoint_ + 1) % viewpoints(ctx).size();
        enter(Step::Reposition, ctx.t);
      }
      break;
    }
    case Step::Reposition:
      if (watch_points_.empty()) {
        if (fresh_) ctx.autopilot.go_to({viewpoints(ctx)[viewpoint_], yaw}, ctx.t);
        fresh_ = false;
        if (face_seen(ctx)) enter(Step::Follow, ctx.t);
        else if (ctx.autopilot.reached() || ctx.t - since_ > 15.0) enter(Step::Sweep, ctx.t);
        break;
      }
      if (fresh_) ctx.autopilot.go_to(transit_[transit_leg_], ctx.t);
      fresh_ = false;
      if (face_seen(ctx)) {
        enter(Step::Follow, ctx.t);
      } else if (ctx.autopilot.reached() || ctx.t - since_ > 15.0) {
        if (++transit_leg_ < transit_.size()) enter(Step::Reposition, ctx.t);
        else enter(Step::Watch, ctx.t);
      }
      break;
    case Step::Watch:
      // Hold at the watch point, facing the oncoming teacher, for one round of the route.
      if (fresh_) ctx.autopilot.go_to({watch_.position, watch_.yaw}, ctx.t, false);
      fresh_ = false;
      if (face_seen(ctx)) {
        enter(Step::Follow, ctx.t);
      } else if (ctx.t - since_ > ctx.lab.teacher.cycle_s() + kWatchMarginS) {
        viewpoint_ = (viewpoint_ + 1) % watch_points_.size();
        meeting_ = false;
        watch_ = watch_points_[viewpoint_];
        plan_transit(ctx, watch_);
        enter(Step::Reposition, ctx.t);
      }
      break;
    case Step::Follow:
      if (face_seen(ctx)) follow(ctx);
      else enter(Step::Lost, ctx.t);
      break;
    case Step::Lost:
      lost(ctx);
      break;
    case Step::Done:
      ctx.focus.face = false;
      break;
  }
  const bool searching = step_ == Step::Sweep || step_ == Step::Reposition || step_ == Step::Watch;
  if (searching && ctx.t - search_started_ > m.face_search_timeout_s) {
    result_ = "no face found in " + format_seconds(m.face_search_timeout_s) + " s";
    ctx.autopilot.hold_here(ctx.pose, ctx.t);
    stage_text_ = "failed: " + result_;
    return MissionOutcome::Failed;
  }
  stage_text_ = describe(ctx.t);
  last_tick_ = ctx.t;
  return step_ == Step::Done ? MissionOutcome::Succeeded : MissionOutcome::Running;
}

MissionOutcome ReturnHomeMission::step(MissionContext& ctx) {
  const HomeLanding::Step s = home_.step(ctx);
  stage_text_ = home_.describe(ctx.t);
  if (s == HomeLanding::Step::Failed) {
    result_ = home_.failure();
    return MissionOutcome::Failed;
  }
  if (s != HomeLanding::Step::Landed) return MissionOutcome::Running;
  result_ = "returned home (" + why_ + ") and landed" + (home_.failure().empty() ? " on the platform" : ": " + home_.failure());
  return MissionOutcome::Succeeded;
}

}  // namespace labo
