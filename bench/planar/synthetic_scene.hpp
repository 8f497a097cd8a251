#pragma once
// Synthetic images with known geometry, for the planar benchmark and tests: a procedural instrument
// panel, a cluttered background, and views of a textured plane through a (distorted) camera at a
// known pose. Deterministic for a given seed.
#include <cstdint>
#include <vector>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "core/camera_model.hpp"

namespace labo::bench {

// A grey front panel: display with a trace, knobs, buttons, labels, screws.
cv::Mat make_procedural_panel(cv::Size size, std::uint32_t seed);
// A textured background (shapes of various grey levels and sizes, mild noise).
cv::Mat make_clutter_background(cv::Size size, std::uint32_t seed);

// Draws `templ` into `scene` (CV_8UC1) through H (template px -> scene px), anti-aliased by
// downscaling the template first when it appears smaller.
void draw_template(const cv::Mat& templ, const cv::Matx33d& H, cv::Mat& scene);

// Renders a planar object (object frame of planar_template.hpp) through a camera, distortion
// included, in front of a textured wall parallel to it `wall_depth_m` behind; the camera's rays are
// computed once. Each pixel over the panel is the template's mean over the pixel's footprint (the
// texels piecewise constant), blended with the wall by the share of the footprint off the panel: what
// a camera's pixel integrates. Used for sequences with ground truth when the simulated lab is not at hand.
class PlanarViewRenderer {
 public:
  // `wall` is tiled at `wall_m_per_px`; an empty wall renders flat grey.
  PlanarViewRenderer(const PinholeCamera& camera, cv::Mat wall, double wall_m_per_px, double wall_depth_m = 0.05);
  cv::Mat render(const cv::Mat& templ, double width_m, double height_m, const Eigen::Isometry3d& T_cam_object) const;
  const PinholeCamera& camera() const { return camera_; }

 private:
  PinholeCamera camera_;
  std::vector<Eigen::Vector3f> rays_;  // unit rays, row-major
  cv::Mat wall_;
  double wall_m_per_px_;
  double wall_depth_m_;
};

// A camera pose in the object frame looking at `target` (object frame), image "down" along the
// object's y as far as possible, rolled by `roll_rad` about the line of sight; returns T_cam_object.
Eigen::Isometry3d look_at_object(const Eigen::Vector3d& camera_in_object, const Eigen::Vector3d& target,
                                 double roll_rad = 0.0);

}  // namespace labo::bench
