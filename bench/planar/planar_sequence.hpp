#pragma once
// One sequence of the planar bench (sequence_bench.hpp): rendered frames with the panel's true pose,
// and what the bench needs to score them.
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "core/camera_model.hpp"

namespace labo::bench {

struct PanelModel {
  cv::Mat image;
  double width_m = 0, height_m = 0;
};

struct PlanarSequence {
  std::string name;
  PanelModel panel;
  bool bottom_camera = false;
  std::vector<cv::Mat> frames;
  std::vector<Eigen::Isometry3d> truth;  // T_cam_object
  std::vector<bool> in_view;
  bool pooled = true;       // in the all-sequence range bins (false: the H.264 sequence's extra noise seeds)
  bool h264_seed = false;   // one of the H.264 sequence's noise seeds
  // The object's own lambda and N (the lab's platform: 1.0 m, 12); the "vision" section's otherwise.
  std::optional<double> sift_switch_distance_m;
  std::optional<int> sift_min_inliers;
};

// The fraction of a 9x9 grid of panel points that project inside the image.
double visible_fraction(const PinholeCamera& camera, const PanelModel& panel, const Eigen::Isometry3d& T_cam_object);

}  // namespace labo::bench
