#include "localization/planar/track/homography_tracker.hpp"

#include "localization/planar/track/ecc_tracker.hpp"
#include "localization/planar/track/ic_tracker.hpp"

namespace labo::planar {

std::unique_ptr<HomographyTracker> make_homography_tracker(TrackerKind kind, const cv::Mat& template_gray,
                                                           const PlanarConfig& config) {
  if (kind == TrackerKind::Ecc) return std::make_unique<EccTracker>(template_gray, config);
  return std::make_unique<InverseCompositionalTracker>(template_gray, config);
}

}  // namespace labo::planar
