#include "control/dead_reckoning_pipelines.hpp"

#include <algorithm>
#include <cmath>

#include "core/frames.hpp"

namespace labo {

namespace {
constexpr double kDriftPerMetre = 0.05;  // 1-sigma position growth per metre travelled
constexpr double kMaxNavGapS = 0.5;
}  // namespace

void DeadReckoningPipelines::reset(const Eigen::Isometry3d& T_world_body, Seconds t) {
  p_ = T_world_body.translation();
  yaw_ = ypr_from_rotation(T_world_body.linear())[0];
  yaw_anchored_ = false;  // the next navdata yaw is mapped onto yaw_
  v_world_.setZero();
  travelled_m_ = 0;
  t_ = t;
}

void DeadReckoningPipelines::on_navdata(const NavdataSample& s) {
  if (!yaw_anchored_) {
    yaw_offset_ = wrap_angle(yaw_ - s.yaw_rad);
    yaw_anchored_ = true;
    last_raw_yaw_ = s.yaw_rad;
  }
  const double dt = have_nav_ ? std::clamp(s.t - t_, 0.0, kMaxNavGapS) : 0.0;
  yaw_rate_ = dt > 0 ? wrap_angle(s.yaw_rad - last_raw_yaw_) / dt : 0.0;
  last_raw_yaw_ = s.yaw_rad;
  yaw_ = wrap_angle(s.yaw_rad + yaw_offset_);
  pitch_ = s.pitch_rad;
  roll_ = s.roll_rad;
  const double c = std::cos(yaw_), sn = std::sin(yaw_);
  const Eigen::Vector3d v(c * s.vx_mps - sn * s.vy_mps, sn * s.vx_mps + c * s.vy_mps, s.vz_mps);
  p_.head<2>() += 0.5 * (v_world_.head<2>() + v.head<2>()) * dt;
  travelled_m_ += v.head<2>().norm() * dt;
  p_.z() = s.altitude_m;
  v_world_ = v;
  t_ = s.t;
  have_nav_ = true;
}

PoseEstimate DeadReckoningPipelines::predict(Seconds t) const {
  PoseEstimate e;
  e.valid = have_nav_;
  e.t = t;
  const double dt = std::clamp(t - t_, 0.0, kMaxNavGapS);
  Eigen::Vector3d p = p_;
  p.head<2>() += v_world_.head<2>() * dt;
  // The ultrasound reports the height above the surface; the filter does better, we take it as z.
  e.T_world_body = make_pose(p, yaw_ + yaw_rate_ * dt, pitch_, roll_);
  e.velocity_world = v_world_;
  e.yaw_rate = yaw_rate_;
  e.source = FeedbackSource::DeadReckoning;
  e.quality = 0.3;
  e.position_sigma_m = kDriftPerMetre * travelled_m_;
  return e;
}

}  // namespace labo
