#pragma once
// OpenCV's findTransformECC (homography model) as a HomographyTracker: the paper's tracker. The search
// runs on a crop around the prior (ECC blurs its whole input), with the template level matching the
// object's apparent size. OpenCV throws when ECC does not converge: the exception becomes a failed
// outcome. ECC allocates inside OpenCV on every call; that cannot be avoided from outside.
#include <vector>

#include "localization/planar/track/homography_tracker.hpp"

namespace labo::planar {

class EccTracker final : public HomographyTracker {
 public:
  EccTracker(const cv::Mat& template_gray, const PlanarConfig& config);
  HomographyTrackOutcome track(const cv::Mat& image, const cv::Matx33d& H_prior) override;
  TrackerKind kind() const override { return TrackerKind::Ecc; }

 private:
  std::vector<cv::Mat> template_levels_;  // CV_32F, level 0 = working template
  cv::Mat roi_float_;  // reused buffer
  PlanarConfig config_;
};

}  // namespace labo::planar
