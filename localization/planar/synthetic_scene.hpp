#pragma once
// Synthetic images with known geometry, for the planar benchmark and tests: a procedural instrument
// panel, a cluttered background, and views of a textured plane through a (distorted) camera at a
// known pose. Deterministic for a given seed.
#include <cstdint>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "core/camera_model.hpp"

namespace labo {

// A grey front panel: display with a trace, knobs, buttons, labels, screws.
cv::Mat make_procedural_panel(cv::Size size, std::uint32_t seed);
// A textured background (shapes of various grey levels and sizes, mild noise).
cv::Mat make_clutter_background(cv::Size size, std::uint32_t seed);

// Draws `templ` into `scene` (CV_8UC1) through H (template px -> scene px), anti-aliased by
// downscaling the template first when it appears smaller.
void draw_template(const cv::Mat& templ, const cv::Matx33d& H, cv::Mat& scene);

// The view of a planar object (object frame of planar_template.hpp) of physical size width_m x
// height_m at T_cam_object through `camera`, distortion included, over `background` (which must
// have the camera's size). Pixels whose ray misses the panel keep the background.
cv::Mat render_planar_view(const cv::Mat& templ, double width_m, double height_m, const Eigen::Isometry3d& T_cam_object,
                           const PinholeCamera& camera, const cv::Mat& background);

}  // namespace labo
