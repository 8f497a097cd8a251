#pragma once
// Relocalizer: after tracking is lost, rank the keyframes by how much their small blurry image
// (40 px wide, zero mean) resembles the frame's (PTAM's idea), then for the best few match the
// frame's descriptors against the keyframe's mapped features, solve PnP with RANSAC and refine.
// The caller confirms the pose by a normal tracking pass.
#include <optional>
#include <vector>

#include "localization/slam/camera/ideal_camera.hpp"
#include "localization/slam/map/slam_map.hpp"

namespace labo::slam {

// Small blurry image of a grey frame: CV_32F, 40 px wide, Gaussian-blurred, zero mean.
cv::Mat small_blurry_image(const cv::Mat& gray);

struct RelocalizationCandidate {
  Eigen::Isometry3d T_cam_map;
  int keyframe = -1;
  int inliers = 0;
};

class Relocalizer {
 public:
  explicit Relocalizer(const IdealCamera& camera, int keyframes_tried = 3);
  // Reads the map under its shared lock.
  std::optional<RelocalizationCandidate> relocalize(const SlamMap& map, const FrameFeatures& frame,
                                                    const cv::Mat& small_image) const;

 private:
  const IdealCamera& camera_;
  int keyframes_tried_;
};

}  // namespace labo::slam
