#pragma once
// The SLAM front-end: SlamSystem (localization/slam/) on the front camera's frames. Its camera pose
// is in map units; LabPipelines hands it to the StateEstimator, whose ScaleEstimator makes it metric
// (the scale manoeuvre of the inspect mission's stage 1) and places the map in the world. While the
// bottom camera streams, SLAM sees nothing and is reported off; it relocalizes on the next front
// frames.
#include <memory>

#include "localization/fusion/vision_front_end.hpp"
#include "localization/slam/slam_system.hpp"

namespace labo::fusion {

class SlamSystemFrontEnd final : public SlamFrontEnd {
 public:
  explicit SlamSystemFrontEnd(std::unique_ptr<slam::SlamSystem> slam);

  const SlamFrame& process(const cv::Mat& gray, Seconds t, const std::optional<Eigen::Isometry3d>& prior_T_cam_map,
                           const std::optional<Eigen::Vector3d>& gravity_down_cam = std::nullopt) override;
  const SlamFrame& pause() override;
  int map_id() const override { return frame_.map_id; }
  // Once every kMapPointsPeriodS of frame time, at most kMaxMapPoints points.
  bool sample_map_points(Seconds t, std::vector<Eigen::Vector3d>& out) override;
  static constexpr double kMapPointsPeriodS = 1.0;
  static constexpr std::size_t kMaxMapPoints = 3000;

  // Drops the map; the next map gets a new id (the estimator restarts its map-to-world placement).
  void restart_map();
  const slam::SlamResult& last_result() const { return result_; }
  slam::SlamSystem& system() { return *slam_; }

 private:
  std::unique_ptr<slam::SlamSystem> slam_;
  slam::SlamResult result_;
  SlamFrame frame_;
  std::optional<Seconds> points_sampled_t_;
};

SlamState slam_state_of(slam::TrackingState state);

}  // namespace labo::fusion
