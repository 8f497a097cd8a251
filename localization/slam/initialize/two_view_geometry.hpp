#pragma once
// Two-view reconstruction for map initialization: from matched ideal pixels, fit both an essential
// matrix and a homography with RANSAC, score each by its truncated transfer error over all matches,
// keep the homography when it explains the matches clearly better (a planar or low-parallax scene),
// recover the relative pose and triangulate. Fails with a reason when the geometry is not
// trustworthy (too few points in front, too little parallax, ambiguous homography decomposition).
#include <Eigen/Geometry>
#include <optional>
#include <string>
#include <vector>

#include "localization/slam/camera/ideal_camera.hpp"

namespace labo::slam {

enum class TwoViewModel { Essential, Homography };

struct TwoViewSettings {
  int min_points = 60;
  double min_parallax_deg = 1.0;     // median triangulation angle
  double ransac_threshold_px = 1.5;
  double homography_ratio = 0.45;    // S_H / (S_H + S_E) above this picks the homography
};

struct TwoViewReconstruction {
  TwoViewModel model = TwoViewModel::Essential;
  double homography_share = 0;          // S_H / (S_H + S_E)
  Eigen::Isometry3d T_second_first;     // |t| = 1
  std::vector<int> match_index;         // which input matches were triangulated
  std::vector<Eigen::Vector3d> points;  // in the first camera's frame
  double median_parallax_deg = 0;
};

struct TwoViewOutcome {
  std::optional<TwoViewReconstruction> reconstruction;
  std::string reason;  // when empty
};

TwoViewOutcome reconstruct_two_views(const IdealCamera& camera, const std::vector<Eigen::Vector2d>& first,
                                     const std::vector<Eigen::Vector2d>& second, const TwoViewSettings& settings);

// Linear triangulation of one point from two poses (camera-from-frame) and ideal pixels; empty when
// the point lands behind either camera.
std::optional<Eigen::Vector3d> triangulate(const IdealCamera& camera, const Eigen::Isometry3d& T_a, const Eigen::Vector2d& px_a,
                                           const Eigen::Isometry3d& T_b, const Eigen::Vector2d& px_b);

}  // namespace labo::slam
