#pragma once
// PatchAligner: sub-pixel position of a map point in a frame, from the image patch around the
// point's feature in its source keyframe (PTAM's idea, written from the description in
// shared/notes/slam_web.md §A). The descriptor match only says which FAST corner the point is; a
// FAST corner sits on an integer pixel of its pyramid level (3.4 level-0 pixels at level 3) and
// shifts with the viewpoint. Here the source patch is warped into the frame by the affine map the
// point's depth and the two poses predict (lens distortion included: both images are real,
// distorted images), at the frame's pyramid level where the warp is closest to a unit scale, and
// aligned by inverse-compositional Gauss-Newton on the translation and a brightness offset,
// starting from the matched corner. A measurement is returned only when the alignment converged
// close to its start: otherwise the caller keeps the corner.
#include <Eigen/Geometry>
#include <array>
#include <opencv2/core.hpp>
#include <optional>
#include <vector>

#include "localization/slam/camera/ideal_camera.hpp"

namespace labo::slam {

// The image a point's patch is cut from: a keyframe's pyramid (8-bit, as features were found on it),
// its pose, and the point's feature there.
struct PatchSource {
  const std::vector<cv::Mat>* pyramid = nullptr;
  Eigen::Isometry3d T_cam_map = Eigen::Isometry3d::Identity();
  Eigen::Vector2d image_px = Eigen::Vector2d::Zero();  // distorted level-0 pixel of the feature
  int level = 0;
};

struct AlignedPosition {
  Eigen::Vector2d image_px;  // distorted level-0 pixel
  int level = 0;             // pyramid level of the frame it was aligned on
};

struct PatchAlignerSettings {
  int max_iterations = 10;
  double converged_px = 0.03;     // step below which the alignment stops (level pixels)
  double max_shift_px = 1.5;      // farther from the corner than this (level pixels): not accepted
  double max_residual_ratio = 0.5;  // RMS residual over the template's standard deviation
};

class PatchAligner {
 public:
  PatchAligner(const IdealCamera& camera, const PatchAlignerSettings& settings = {});

  // p_map: the point; frame: the frame's pyramid; T_cam_map: the frame's pose (a prior is enough);
  // start_image_px: the matched corner (distorted level-0 pixel).
  std::optional<AlignedPosition> align(const PatchSource& source, const Eigen::Vector3d& p_map,
                                       const std::vector<cv::Mat>& frame, const Eigen::Isometry3d& T_cam_map,
                                       const Eigen::Vector2d& start_image_px);

 private:
  static constexpr int kHalf = 4;               // aligned window: (2 * kHalf + 1)^2 pixels
  static constexpr int kSide = 2 * kHalf + 3;   // template with a one-pixel rim for its gradients
  bool warp_template(const PatchSource& source, const Eigen::Matrix2d& source_from_frame, const cv::Mat& source_image);

  const IdealCamera& camera_;
  PatchAlignerSettings settings_;
  std::array<float, kSide * kSide> template_{};
};

}  // namespace labo::slam
