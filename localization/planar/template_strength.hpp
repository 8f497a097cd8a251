#pragma once
// How well a panel's template can be found and followed, measured before an instrument is accepted
// (an admin's upload): SIFT keypoints (the paper's near detector accepts a detection from N = 20
// inliers, and only a share of a template's keypoints match a frame taken from metres away, so it
// needs several times that many), strong corners (what the trackers lock on), and how much of the
// panel carries texture (texture in one corner only gives an ill-conditioned homography). Measured on
// the template scaled to kMeasureSidePx on its long side, about what the camera sees of a panel
// near the standoff, and bounded in cost whatever the upload's size.
#include <opencv2/core.hpp>
#include <string>

namespace labo::planar {

struct TemplateStrength {
  int sift_keypoints = 0;
  int strong_corners = 0;
  double textured_fraction = 0;  // of the panel's 8 x 8 cells whose mean gradient shows texture
};

struct TemplateStrengthLimits {
  int min_sift_keypoints = 60;
  int min_strong_corners = 40;
  double min_textured_fraction = 0.3;
};

inline constexpr int kMeasureSidePx = 640;

// `gray`: 8-bit, one channel.
TemplateStrength measure_template_strength(const cv::Mat& gray);
// Empty when the template is strong enough; else why not (each measure short of its limit, with both).
std::string template_weakness(const TemplateStrength& strength, const TemplateStrengthLimits& limits = {});

}  // namespace labo::planar
