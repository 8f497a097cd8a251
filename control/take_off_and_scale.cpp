#include "control/take_off_and_scale.hpp"

#include <algorithm>
#include <cmath>

#include "core/frames.hpp"

namespace labo::control {

namespace {
constexpr double kClimbTimeoutS = 8.0;
constexpr double kSlamInitTimeoutS = 8.0;  // go on (on dead reckoning) when SLAM does not initialize
constexpr double kAtHeightM = 0.1;         // a leg ends when the drone is this close to its end
constexpr double kLegTimeoutS = 8.0;       // the forward or back leg is given up after this long
}  // namespace

std::string TakeOffAndScale::describe() const {
  const std::string scale = slam_.scale_estimated ? "scale fixed"
                                                   : "waiting for scale: " + std::to_string(slam_.scale_pairs) + "/" +
                                                         std::to_string(slam_.scale_pairs_needed) + " pairs";
  switch (step_) {
    case Step::TakeOff: return "taking off";
    case Step::Climb: return "climbing to " + format_seconds(altitude_m_) + " m";
    case Step::SlamInit:
      return "initializing SLAM: waiting for a map (" + format_seconds(last_t_ - since_) + " s of " +
             format_seconds(kSlamInitTimeoutS) + " s)";
    case Step::Forward: return "scale manoeuvre (forward): " + scale;
    case Step::Back: return "scale manoeuvre (back): " + scale;
    case Step::Up:
    case Step::Down: {
      const std::string leg = step_ == Step::Up ? "scale manoeuvre (up" : "scale manoeuvre (down";
      return (round_ > 0 ? leg + ", round " + std::to_string(round_ + 1) + " of " + std::to_string(kMaxRounds) + ")" : leg + ")") +
             ": " + scale;
    }
    case Step::Done: return "scale manoeuvre done: " + scale;
  }
  return "";
}

bool TakeOffAndScale::step(MissionContext& ctx, double altitude_m) {
  const auto& m = ctx.config.mission;
  const Eigen::Vector3d here = ctx.pose.T_world_body.translation();
  const double yaw = ypr_from_rotation(ctx.pose.T_world_body.linear())[0];
  ctx.focus.slam = true;
  altitude_m_ = altitude_m;
  last_t_ = ctx.t;
  slam_ = ctx.perception.slam();
  switch (step_) {
    case Step::TakeOff:
      if (ctx.autopilot.phase() == FlightPhase::Landed) ctx.phase_action = ctx.autopilot.takeoff(ctx.t);
      if (ctx.autopilot.flying()) enter(Step::Climb, ctx.t);
      break;
    case Step::Climb:
      if (fresh_) ctx.autopilot.go_to({{here.x(), here.y(), altitude_m}, yaw}, ctx.t);
      fresh_ = false;
      if (ctx.autopilot.reached() || ctx.t - since_ > kClimbTimeoutS) enter(Step::SlamInit, ctx.t);
      break;
    case Step::SlamInit: {
      const fusion::SlamState s = ctx.perception.slam().state;
      if (s == fusion::SlamState::Good || s == fusion::SlamState::Dodgy || ctx.t - since_ > kSlamInitTimeoutS) {
        leg_start_ = ctx.autopilot.target().value_or(PoseTarget{here, yaw});
        start_z_ = leg_start_.position.z();
        enter(m.scale_manoeuvre_m > 0 ? Step::Forward : Step::Done, ctx.t);
      }
      break;
    }
    case Step::Forward:
    case Step::Back: {
      const bool forward = step_ == Step::Forward;
      const Eigen::Vector3d ahead(std::cos(leg_start_.yaw), std::sin(leg_start_.yaw), 0.0);
      const PoseTarget target{leg_start_.position + (forward ? m.scale_manoeuvre_m : 0.0) * ahead, leg_start_.yaw};
      if (fresh_) ctx.autopilot.go_to(target, ctx.t);
      fresh_ = false;
      const bool leg_done = (here - target.position).norm() < kAtHeightM || ctx.t - since_ > kLegTimeoutS;
      if (leg_done) enter(forward ? Step::Back : Step::Up, ctx.t);
      break;
    }
    case Step::Up:
    case Step::Down: {
      // A set point moving at a slow, steady speed: the vertical motion the scale estimator needs.
      const bool up = step_ == Step::Up;
      const double travelled = std::min(m.scale_manoeuvre_speed_mps * (ctx.t - since_), m.scale_manoeuvre_m);
      const double z = up ? start_z_ + travelled : start_z_ + m.scale_manoeuvre_m - travelled;
      const PoseTarget base_target = ctx.autopilot.target().value_or(PoseTarget{here, yaw});
      ctx.autopilot.go_to({{base_target.position.x(), base_target.position.y(), z}, base_target.yaw}, ctx.t, fresh_ && up);
      fresh_ = false;
      const bool leg_done = travelled >= m.scale_manoeuvre_m && std::abs(here.z() - z) < kAtHeightM;
      const bool timed_out = ctx.t - since_ > 3.0 * m.scale_manoeuvre_m / m.scale_manoeuvre_speed_mps + 5.0;
      if (leg_done && up) {
        enter(Step::Down, ctx.t);
      } else if (leg_done && !ctx.perception.slam().scale_estimated && round_ + 1 < kMaxRounds) {
        ++round_;  // no scale yet: another round (SLAM itself may have restarted its map meanwhile)
        enter(Step::Up, ctx.t);
      } else if (leg_done || timed_out) {
        enter(Step::Done, ctx.t);
      }
      break;
    }
    case Step::Done:
      break;
  }
  return step_ == Step::Done;
}

}  // namespace labo::control
