#pragma once
// Frame-to-frame homography trackers: given the previous homography (working template pixels ->
// image pixels) as the prior, align the template to the new frame. Two implementations, selected by
// PlanarConfig::tracker: OpenCV's findTransformECC and LaboDrone's inverse-compositional tracker.
#include <memory>

#include <opencv2/core.hpp>

#include "localization/planar/planar_config.hpp"

namespace labo::planar {

struct HomographyTrackOutcome {
  bool converged = false;
  cv::Matx33d H = cv::Matx33d::eye();  // working template px -> image px
  double correlation = 0;              // zero-mean normalized correlation after alignment, [-1, 1]
  int iterations = 0;                  // summed over pyramid levels
  const char* failure = "";            // why not converged (static text)
};

class HomographyTracker {
 public:
  virtual ~HomographyTracker() = default;
  // `image` is CV_8UC1. Never throws on bad convergence: the outcome says so.
  virtual HomographyTrackOutcome track(const cv::Mat& image, const cv::Matx33d& H_prior) = 0;
  virtual TrackerKind kind() const = 0;
};

// `template_gray` is the working template (CV_8UC1); it is copied.
std::unique_ptr<HomographyTracker> make_homography_tracker(TrackerKind kind, const cv::Mat& template_gray,
                                                           const PlanarConfig& config);

// The template pyramid level whose resolution matches the object's appearance under H (the object
// as large in the image as the template at that level, or larger): 0 when the object appears at full
// template size, 1 at half size, ...; at most `max_level`.
int matching_template_level(const cv::Matx33d& H, cv::Size template_size, int max_level);

}  // namespace labo::planar
