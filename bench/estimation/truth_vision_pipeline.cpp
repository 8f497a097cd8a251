#include "bench/estimation/truth_vision_pipeline.hpp"

#include <cmath>

#include "core/frames.hpp"

namespace labo::bench {

namespace {
Eigen::Isometry3d perturbed(const Eigen::Isometry3d& T, double sigma_t, double sigma_r, std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  Eigen::Isometry3d out = T;
  out.translation() += sigma_t * Eigen::Vector3d(n(rng), n(rng), n(rng));
  out.linear() = out.linear() * rotation_from_ypr(sigma_r * n(rng), sigma_r * n(rng), sigma_r * n(rng));
  return out;
}
}  // namespace

TruthVisionPipeline::TruthVisionPipeline(const estimation::EstimatorConfig& config, const VisionThresholds& thresholds,
                                         const EstimationPlant& plant, unsigned seed)
    : estimator_(config, thresholds), instrument_(plant.instrument()), video_delay_(plant.video_delay()),
      rng_(seed * 7919u + 13u) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  T_map_world_ = make_pose(Eigen::Vector3d(u(rng_), u(rng_), u(rng_)), M_PI * u(rng_), 0.3 * u(rng_), 0.3 * u(rng_));
  metres_per_unit_ = std::exp(std::log(0.4) + (std::log(2.5) - std::log(0.4)) * 0.5 * (u(rng_) + 1.0));
  estimator_.set_surface_map(plant.surfaces());
  slam_track_.reserve(4096);
}

std::string TruthVisionPipeline::vision_input() const {
  return "ground-truth-derived visual poses with noise and the plant's video delay (SLAM: random map frame and "
         "scale, 1.5 cm / 0.5 deg; instrument: 3 mm + 4 mm*d^2 / 0.7 deg while in view); not the SLAM/planar "
         "front-ends";
}

void TruthVisionPipeline::on_truth(const GroundTruth& truth, Seconds now) {
  frames_.emplace_back(now + video_delay_, truth.T_world_body);
  while (!frames_.empty() && frames_.front().first <= now + 1e-9) {
    const auto [t_arrival, T_world_body] = frames_.front();
    frames_.pop_front();
    deliver(t_arrival, T_world_body);
  }
}

void TruthVisionPipeline::deliver(Seconds t_arrival, const Eigen::Isometry3d& T_world_body) {
  const Eigen::Isometry3d T_world_cam = T_world_body * T_body_cam_front();
  if (wanted_.slam) {
    estimation::SlamObservation o;
    o.t = t_arrival;
    Eigen::Isometry3d T = T_map_world_ * perturbed(T_world_cam, 0.015, 0.5 * M_PI / 180.0, rng_);
    T.translation() /= metres_per_unit_;
    o.T_map_cam = T;
    o.quality = 0.8;
    estimator_.add_slam_pose(o);
    slam_track_.push_back({o.t, o.T_map_cam, o.map_id});
  }
  if (wanted_.instrument) {
    const Eigen::Isometry3d T_cam_object = T_world_cam.inverse() * instrument_.T_world_object;
    const Eigen::Vector3d p = T_cam_object.translation();
    const double d = p.norm();
    if (p.z() > 0.2 && std::abs(p.x() / p.z()) < 0.8 && std::abs(p.y() / p.z()) < 0.45 && d < 4.0) {
      estimation::ObjectObservation o;
      o.t = t_arrival;
      o.object_index = 0;
      o.T_cam_object = perturbed(T_cam_object, 0.003 + 0.004 * d * d, 0.7 * M_PI / 180.0, rng_);
      o.T_world_object_surveyed = instrument_.T_world_object;
      o.quality = 0.9;
      estimator_.add_object_pose(o);
    }
  }
}

}  // namespace labo::bench
