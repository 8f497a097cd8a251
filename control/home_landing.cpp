#include "control/home_landing.hpp"

#include <algorithm>
#include <array>

#include "core/frames.hpp"

namespace labo::control {

namespace {
constexpr double kPlatformSettleS = 0.5;  // platform seen this long before centring on it
constexpr double kLandedWaitS = 12.0;     // land sent; give up waiting after this
// Settled above the platform: the firmware's descent keeps the horizontal speed it starts with for a
// moment, and a climb or descent still under way ends below or above the hover height.
constexpr double kSettledSpeedMps = 0.05;
constexpr double kSettledAltitudeM = 0.1;

// The platform not seen above the base: the estimate drifted more than the bottom camera's view
// covers. The AR.Drone's (640 x 360, f 700 px) sees +-0.41 m along the heading and +-0.73 m across at
// the 1.6-m return altitude, so the pattern looks 0.6 m ahead and behind first (the narrow axis),
// then at the four corners 0.8 m aside: together about +-1.0 m along and +-1.5 m across. Offsets in
// the base's frame (x along its heading, y to its left).
constexpr std::array<std::array<double, 2>, 6> kSearchOffsetsM = {
    {{0.6, 0.0}, {-0.6, 0.0}, {-0.6, 0.8}, {0.6, 0.8}, {0.6, -0.8}, {-0.6, -0.8}}};
constexpr double kSearchFirstLookS = 3.0;  // above the base before the pattern starts
constexpr double kSearchDwellS = 1.5;      // at each point: the detector's settle and a few frames
constexpr double kSearchLegS = 5.0;        // a leg not reached by then looks from where it is
// Centring, the platform out of view this long: the drone holds a place the platform is not under (a
// drift the estimate did not see), not a few frames the tracker refused. Search again from the
// estimate, a bounded number of times.
constexpr double kPlatformLostS = 3.0;
constexpr int kMaxSearchRestarts = 2;

// The centring tolerance widens from landing_centre_tolerance_m to this many times it by the
// platform_settle_timeout_s: where the platform as seen jitters by more than the tolerance (a bottom
// camera off its calibration, frames the tracker refuses), the drone lands at a moment it is nearly
// centred rather than from wherever the timeout finds it (which was up to 6 cm off as seen).
constexpr double kCentreToleranceGrowth = 2.0;

double centre_tolerance_m(const MissionParameters& m, Seconds centring_for) {
  const double progress = std::clamp(centring_for / m.platform_settle_timeout_s, 0.0, 1.0);
  return m.landing_centre_tolerance_m * (1.0 + (kCentreToleranceGrowth - 1.0) * progress);
}

// Where the bottom camera sees the platform, from where the drone is: not the estimator's placement
// of it, which also leans on the lab file's and on the map's (the placement's pull put the drone
// up to 7 cm off a platform the camera had centred). The frame's own attitude when known.
Eigen::Vector3d platform_as_seen(const fusion::TargetObservation& obs, const fusion::PoseEstimate& pose) {
  if (!obs.offset_heading_m) return place_in_world(pose, CameraId::Bottom, obs.T_cam_target).translation();
  const double yaw = ypr_from_rotation(pose.T_world_body.linear())[0];
  return pose.T_world_body.translation() + Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) * *obs.offset_heading_m;
}
}  // namespace

int HomeLanding::paper_stage() const {
  switch (step_) {
    case Step::Climb:
    case Step::Travel: return 4;
    case Step::FindPlatform:
    case Step::Centre: return 5;
    default: return 6;
  }
}

std::string HomeLanding::describe(Seconds t) const {
  switch (step_) {
    case Step::Climb: return "4 return: climbing to the return altitude";
    case Step::Travel: return "4 return: flying above the base";
    case Step::FindPlatform:
      if (search_point_ < 0 || search_point_ >= static_cast<int>(kSearchOffsetsM.size()))
        return "5 platform: searching with the bottom camera (" + format_seconds(t - since_) + " s)";
      return "5 platform: searching around the base (look " + std::to_string(search_point_ + 1) + " of " +
             std::to_string(kSearchOffsetsM.size()) + ", " + format_seconds(t - since_) + " s)";
    case Step::Centre: return "5 platform: hovering above its centre";
    case Step::Land: return "6 landing";
    case Step::Landed: return "6 landed on the platform";
    case Step::Failed: return "failed: " + failure_;
  }
  return "";
}

HomeLanding::Step HomeLanding::step(MissionContext& ctx) {
  const Eigen::Vector3d here = ctx.pose.T_world_body.translation();
  const double yaw = ypr_from_rotation(ctx.pose.T_world_body.linear())[0];
  const Eigen::Vector3d base = ctx.lab.base;
  ctx.focus.instrument_id.clear();
  ctx.focus.face = false;
  const Step before = step_;
  const Eigen::Vector3d correction = estimate_correction_.update(ctx.pose, ctx.t);
  if (step_ == Step::Centre) platform_world_.head<2>() += correction.head<2>();
  step_now(ctx, here, yaw, base);
  fresh_ = step_ != before;
  return step_;
}

void HomeLanding::step_now(MissionContext& ctx, const Eigen::Vector3d& here, double yaw, const Eigen::Vector3d& base) {
  const auto& m = ctx.config.mission;
  switch (step_) {
    case Step::Climb:
      ctx.camera = CameraId::Front;
      ctx.focus.platform = false;
      if (fresh_) ctx.autopilot.go_to({{here.x(), here.y(), m.return_altitude_m}, yaw}, ctx.t);
      if (std::abs(here.z() - m.return_altitude_m) < 0.2 || ctx.t - since_ > 8.0) enter(Step::Travel, ctx.t);
      break;
    case Step::Travel: {
      const PoseTarget above{{base.x(), base.y(), m.return_altitude_m}, ctx.lab.base_yaw_rad};
      if (fresh_) ctx.autopilot.go_to(above, ctx.t);
      if (ctx.autopilot.reached()) {
        ctx.camera = CameraId::Bottom;
        ctx.focus.platform = true;
        enter(Step::FindPlatform, ctx.t);
        start_search(ctx.t);
      }
      break;
    }
    case Step::FindPlatform: {
      ctx.camera = CameraId::Bottom;
      ctx.focus.platform = true;
      const fusion::TargetObservation obs = ctx.perception.platform();
      if (obs.state == fusion::TrackState::Tracking && ctx.t - obs.t < 0.5 && ctx.t - since_ > kPlatformSettleS) {
        platform_world_ = platform_as_seen(obs, ctx.pose);
        platform_seen_t_ = obs.t;
        ctx.autopilot.go_to({{platform_world_.x(), platform_world_.y(), m.platform_hover_altitude_m}, ctx.lab.base_yaw_rad}, ctx.t);
        enter(Step::Centre, ctx.t);
      } else {
        search(ctx, base);
      }
      break;
    }
    case Step::Centre: {
      // The platform's place is kept in the estimate's frame (moved with its corrections, step()),
      // refined while it is in view; the set point follows it without a reset.
      const fusion::TargetObservation obs = ctx.perception.platform();
      if (obs.state == fusion::TrackState::Tracking && ctx.t - obs.t < 0.5) {
        platform_world_ = 0.9 * platform_world_ + 0.1 * platform_as_seen(obs, ctx.pose);
        platform_seen_t_ = obs.t;
      } else if (ctx.t - platform_seen_t_ > kPlatformLostS && search_restarts_ < kMaxSearchRestarts) {
        ++search_restarts_;
        enter(Step::FindPlatform, ctx.t);
        restart_search(ctx, base);
        break;
      }
      ctx.autopilot.go_to({{platform_world_.x(), platform_world_.y(), m.platform_hover_altitude_m}, ctx.lab.base_yaw_rad},
                          ctx.t, false);
      const double off_m = (here - platform_world_).head<2>().norm();
      const bool centred = off_m < centre_tolerance_m(m, ctx.t - since_) &&
                           ctx.pose.velocity_world.head<2>().norm() < kSettledSpeedMps &&
                           std::abs(here.z() - m.platform_hover_altitude_m) < kSettledAltitudeM;
      if (!centred) centred_since_ = -1;
      else if (centred_since_ < 0) centred_since_ = ctx.t;
      if (centred_since_ >= 0 && ctx.t - centred_since_ >= m.landing_settle_s) {
        ctx.phase_action = ctx.autopilot.land(ctx.t);
        enter(Step::Land, ctx.t);
      } else if (ctx.t - since_ > m.platform_settle_timeout_s) {
        failure_ = "not settled within " + format_seconds(m.landing_centre_tolerance_m * 100) + "-" +
                   format_seconds(kCentreToleranceGrowth * m.landing_centre_tolerance_m * 100) + " cm of the platform's centre in " +
                   format_seconds(m.platform_settle_timeout_s) + " s; landed from " + format_seconds(off_m * 100) + " cm off";
        ctx.phase_action = ctx.autopilot.land(ctx.t);
        enter(Step::Land, ctx.t);
      }
      break;
    }
    case Step::Land:
      if (ctx.autopilot.phase() == FlightPhase::Landed) enter(Step::Landed, ctx.t);
      else if (ctx.t - since_ > kLandedWaitS) {
        failure_ = "the drone did not report landed";
        enter(Step::Failed, ctx.t);
      }
      break;
    case Step::Landed:
    case Step::Failed:
      break;
  }
}

void HomeLanding::restart_search(MissionContext& ctx, const Eigen::Vector3d& base) {
  const auto& m = ctx.config.mission;
  ctx.autopilot.go_to({{base.x(), base.y(), m.return_altitude_m}, ctx.lab.base_yaw_rad}, ctx.t);
  start_search(ctx.t);
  dwell_since_ = -1;  // on the way back above the base
}

void HomeLanding::search(MissionContext& ctx, const Eigen::Vector3d& base) {
  const auto points = static_cast<int>(kSearchOffsetsM.size());
  if (dwell_since_ < 0 && (ctx.autopilot.reached() || ctx.t - leg_since_ > kSearchLegS)) dwell_since_ = ctx.t;
  const double dwell_s = search_point_ < 0 ? kSearchFirstLookS : kSearchDwellS;
  if (dwell_since_ < 0 || ctx.t - dwell_since_ < dwell_s) return;
  if (search_point_ >= points) {
    // Not seen anywhere: land on the base as estimated (reported, not hidden).
    failure_ = "landing platform not found above the base nor " + std::to_string(points) + " looks around it in " +
               format_seconds(ctx.t - since_) + " s; landing at the estimated base";
    ctx.phase_action = ctx.autopilot.land(ctx.t);
    enter(Step::Land, ctx.t);
    return;
  }
  ++search_point_;
  Eigen::Vector2d offset = Eigen::Vector2d::Zero();  // the last leg: back above the base
  if (search_point_ < points) {
    const auto& o = kSearchOffsetsM[static_cast<std::size_t>(search_point_)];
    offset = Eigen::Rotation2Dd(ctx.lab.base_yaw_rad) * Eigen::Vector2d(o[0], o[1]);
  }
  const auto& m = ctx.config.mission;
  ctx.autopilot.go_to({{base.x() + offset.x(), base.y() + offset.y(), m.return_altitude_m}, ctx.lab.base_yaw_rad}, ctx.t);
  leg_since_ = ctx.t;
  dwell_since_ = -1;
}

}  // namespace labo::control
