#include "bench/experiments/perception_model.hpp"

#include <cmath>

#include "core/frames.hpp"

namespace labo::bench {

namespace {
bool in_view(const Eigen::Isometry3d& T_cam_target, double max_range, double half_w, double half_h) {
  const Eigen::Vector3d p = T_cam_target.translation();
  if (p.z() <= 0.1 || p.z() > max_range) return false;
  return std::abs(p.x() / p.z()) < half_w && std::abs(p.y() / p.z()) < half_h;
}
}  // namespace

PerceptionModel::PerceptionModel(PerceptionModelConfig config, fusion::LabGeometry lab, unsigned seed)
    : config_(config), lab_(std::move(lab)), rng_(seed) {
  // The map starts where SLAM initializes; an arbitrary rigid offset from the world.
  T_map_world_ = make_pose({0.3, -0.2, 0.1}, 0.2);
}

Eigen::Isometry3d PerceptionModel::noisy(const Eigen::Isometry3d& T, double distance) {
  const double s = config_.position_noise_at_1m * distance * distance;
  Eigen::Isometry3d out = T;
  out.translation() += Eigen::Vector3d(gauss(s), gauss(s), gauss(s));
  out.linear() = out.linear() * rotation_from_ypr(gauss(config_.angle_noise_rad), gauss(config_.angle_noise_rad),
                                                  gauss(config_.angle_noise_rad));
  return out;
}

NavdataSample PerceptionModel::navdata(const QuadrotorModel& drone, Seconds t) {
  NavdataSample s = drone.navdata(t);
  s.vx_mps += gauss(config_.navdata_velocity_noise_mps);
  s.vy_mps += gauss(config_.navdata_velocity_noise_mps);
  s.altitude_m = std::max(0.0, s.altitude_m + gauss(config_.navdata_altitude_noise_m));
  return s;
}

void PerceptionFrame::deliver_to(fusion::LabPipelines& pipelines) const {
  if (instrument) pipelines.add_instrument_result(*instrument);
  if (platform) pipelines.add_platform_result(*platform);
  if (face) pipelines.add_face_result(*face);
  pipelines.add_slam_result(T_map_cam, slam, 1, t);
}

PerceptionFrame PerceptionModel::observe(const QuadrotorModel& drone, const Eigen::Isometry3d& T_world_face, Seconds t,
                                         const fusion::PerceptionFocus& focus) {
  PerceptionFrame out;
  out.t = t;
  const bool airborne = drone.control_state == 3 || drone.control_state == 4;
  if (!airborne) airborne_since_ = -1;
  else if (airborne_since_ < 0) airborne_since_ = t;
  const Eigen::Isometry3d T_world_front = drone.pose() * T_body_cam_front();
  const Eigen::Isometry3d T_world_bottom = drone.pose() * T_body_cam_bottom();

  double panel_distance = 1e9;
  if (const fusion::PlanarTarget* inst = lab_.find_instrument(focus.instrument_id)) {
    fusion::TargetObservation o;
    o.t = t;
    const Eigen::Isometry3d T = T_world_front.inverse() * inst->T_world_object;
    const bool seen = in_view(T, config_.instrument_range_m, 0.5, 0.28) && T.linear().col(2).z() > 0.3;
    o.state = seen ? fusion::TrackState::Tracking : fusion::TrackState::Lost;
    o.reason = seen ? "" : "out of view";
    o.method = T.translation().z() > 2.0 ? "template" : "features";
    o.quality = seen ? 0.9 : 0;
    if (seen) o.T_cam_target = noisy(T, T.translation().z());
    out.instrument = o;
  }
  for (const auto& inst : lab_.instruments) {
    const Eigen::Isometry3d T = T_world_front.inverse() * inst.T_world_object;
    if (in_view(T, 10.0, 0.6, 0.4)) panel_distance = std::min(panel_distance, T.translation().z());
  }
  if (focus.platform) {
    fusion::TargetObservation o;
    o.t = t;
    const Eigen::Isometry3d T = T_world_bottom.inverse() * lab_.platform.T_world_object;
    const bool seen = in_view(T, 3.0, 0.45, 0.25);
    o.state = seen ? fusion::TrackState::Tracking : fusion::TrackState::Lost;
    o.method = "template";
    o.quality = seen ? 0.9 : 0;
    if (seen) o.T_cam_target = noisy(T, T.translation().z());
    out.platform = o;
  }
  if (focus.face) {
    fusion::TargetObservation o;
    o.t = t;
    const Eigen::Isometry3d T = T_world_front.inverse() * T_world_face;
    const bool seen = in_view(T, config_.face_range_m, 0.45, 0.25) && T.linear().col(2).z() > 0.3;
    o.state = seen ? fusion::TrackState::Tracking : fusion::TrackState::Lost;
    o.method = "pnp-lm";
    o.quality = seen ? 0.8 : 0;
    if (seen) o.T_cam_target = noisy(T, 1.5 * T.translation().z());
    out.face = o;
  }
  fusion::SlamSummary s;
  if (focus.slam && airborne_since_ >= 0) {
    const bool initialized = t - airborne_since_ >= config_.slam_init_s;
    const bool panel_fills_view = panel_distance < config_.slam_lost_below_m;
    s.state = !initialized ? fusion::SlamState::Initializing : panel_fills_view ? fusion::SlamState::Lost : fusion::SlamState::Good;
    s.points_attempted = 300;
    s.points_found = s.state == fusion::SlamState::Good ? 220 : 20;
    s.keyframes = initialized ? 2 + static_cast<int>((t - airborne_since_) / 5.0) : 0;
    Eigen::Isometry3d T_map_cam = T_map_world_ * noisy(T_world_front, 1.0);
    T_map_cam.translation() += Eigen::Vector3d(gauss(config_.slam_noise_m), gauss(config_.slam_noise_m),
                                               gauss(config_.slam_noise_m));
    T_map_cam.translation() *= config_.map_units_per_m;
    out.T_map_cam = T_map_cam;
  }
  out.slam = s;
  return out;
}

}  // namespace labo::bench
