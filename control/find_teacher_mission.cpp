#include "control/find_teacher_mission.hpp"

#include <cmath>
#include <numbers>

#include "core/frames.hpp"

namespace labo {

namespace {
constexpr double kFaceHeightM = 1.6;       // climb to about a standing teacher's face height
constexpr double kFreshObservationS = 0.3;
constexpr double kLostHoldS = 3.0;         // face lost: hold this long, then search again
constexpr double kFollowSmoothing = 0.5;    // low-pass on the face's place (per face result)
constexpr double kVelocitySmoothing = 0.2;  // low-pass on the teacher's velocity
constexpr double kCoastS = 0.5;             // face lost: keep following its predicted motion this long
}  // namespace

int FindTeacherMission::stage_index() const {
  switch (step_) {
    case Step::TakeOff:
    case Step::Climb: return 1;
    case Step::Sweep:
    case Step::Reposition: return 2;
    default: return 3;
  }
}

std::string FindTeacherMission::describe(Seconds t) const {
  switch (step_) {
    case Step::TakeOff: return "1 take-off";
    case Step::Climb: return "1 climbing to face height";
    case Step::Sweep: return "2 search: yaw sweep at viewpoint " + std::to_string(viewpoint_ + 1);
    case Step::Reposition: return "2 search: moving to viewpoint " + std::to_string(viewpoint_ + 1);
    case Step::Follow: return "3 face-follow";
    case Step::Lost: return "3 face-follow: face lost, holding (" + format_seconds(t - since_) + " s)";
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

void FindTeacherMission::follow(MissionContext& ctx) {
  const TargetObservation f = ctx.perception.face();
  if (f.t == last_face_t_ && !fresh_) return;  // no new face result: keep the moving set point
  Eigen::Isometry3d T_world_face = world_pose_of(f, ctx.pose, CameraId::Front);
  // Low-pass the face's place and estimate the teacher's velocity from it (feed-forward).
  if (fresh_ || last_face_t_ < 0) {
    face_position_ = T_world_face.translation();
    face_velocity_.setZero();
  } else {
    const double dt = std::max(f.t - last_face_t_, 1e-3);
    const Eigen::Vector3d previous = face_position_;
    face_position_ += kFollowSmoothing * (T_world_face.translation() - face_position_);
    Eigen::Vector3d v = (face_position_ - previous) / dt;
    v.z() = 0;
    face_velocity_ += kVelocitySmoothing * (v - face_velocity_);
  }
  last_face_t_ = f.t;
  T_world_face.translation() = face_position_;
  PoseTarget next = standoff_target(T_world_face, ctx.config.mission.face_distance_m, ctx.centre_ray_front);
  next.velocity = face_velocity_;
  // Point the camera at the face from where the drone is: the same as the line of sight once in
  // place, and it keeps a walking teacher in view while the drone catches up.
  const Eigen::Vector3d to_face = face_position_ - ctx.pose.T_world_body.translation();
  next.yaw = std::atan2(to_face.y(), to_face.x());
  ctx.autopilot.go_to(next, ctx.t, fresh_);
  fresh_ = false;
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
    case Step::TakeOff:
      if (ctx.autopilot.phase() == FlightPhase::Landed) ctx.phase_action = ctx.autopilot.takeoff(ctx.t);
      if (ctx.autopilot.flying()) enter(Step::Climb, ctx.t);
      break;
    case Step::Climb:
      if (fresh_) ctx.autopilot.go_to({{here.x(), here.y(), kFaceHeightM}, yaw}, ctx.t);
      fresh_ = false;
      if (ctx.autopilot.reached() || ctx.t - since_ > 8.0) {
        search_started_ = ctx.t;
        enter(Step::Sweep, ctx.t);
      }
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
      if (fresh_) ctx.autopilot.go_to({viewpoints(ctx)[viewpoint_], yaw}, ctx.t);
      fresh_ = false;
      if (face_seen(ctx)) enter(Step::Follow, ctx.t);
      else if (ctx.autopilot.reached() || ctx.t - since_ > 15.0) enter(Step::Sweep, ctx.t);
      break;
    case Step::Follow:
      if (face_seen(ctx)) follow(ctx);
      else enter(Step::Lost, ctx.t);
      break;
    case Step::Lost:
      // Coast along the teacher's last motion (they most likely walked out of view), then hold.
      if (auto target = ctx.autopilot.target(); target && ctx.t - since_ < kCoastS) {
        PoseTarget next = *target;
        next.position += next.velocity * (ctx.t - last_tick_);
        face_position_ += face_velocity_ * (ctx.t - last_tick_);
        ctx.autopilot.go_to(next, ctx.t, false);
      } else if (target) {
        // Hold the place, keep looking where the face went.
        const Eigen::Vector3d to_face = face_position_ - ctx.pose.T_world_body.translation();
        PoseTarget look{target->velocity.norm() > 0 ? ctx.pose.T_world_body.translation() : target->position,
                        std::atan2(to_face.y(), to_face.x())};
        ctx.autopilot.go_to(look, ctx.t, target->velocity.norm() > 0);
      }
      fresh_ = false;
      if (face_seen(ctx)) enter(Step::Follow, ctx.t);
      else if (ctx.t - since_ > kLostHoldS) {
        search_started_ = ctx.t;
        enter(Step::Sweep, ctx.t);
      }
      break;
    case Step::Done:
      ctx.focus.face = false;
      break;
  }
  if ((step_ == Step::Sweep || step_ == Step::Reposition) && ctx.t - search_started_ > m.face_search_timeout_s) {
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
