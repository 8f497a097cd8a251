#pragma once
// The planar-object front-end: an instrument's front panel in the front camera, the landing platform
// in the bottom camera. Wraps PlanarObjectLocalizer (localization/planar/) with the target's template
// and physical size and the paper's thresholds - template matching far and SIFT near, switching at
// the object's lambda, then frame-to-frame tracking until a loss (correlation below alpha, a jump
// beyond D or beta, too little of the panel in view) - and reports a TargetObservation. When the
// detector the predicted distance picked finds nothing, the next frame runs both; a template match of
// that retry far from the predicted distance counts only once the tracker has confirmed it.
#include <filesystem>
#include <optional>

#include "localization/fusion/lab_geometry.hpp"
#include "localization/fusion/vision_front_end.hpp"
#include "core/camera_model.hpp"
#include "localization/planar/planar_localizer.hpp"

namespace labo::fusion {

class PlanarFrontEnd final : public TargetFrontEnd {
 public:
  // Throws std::invalid_argument naming the target when it has no template or the template is
  // unusable (missing file, too little texture; PlanarTemplate's reasons).
  PlanarFrontEnd(const PlanarTarget& target, const PinholeCamera& camera, const VisionThresholds& vision,
                 const planar::PlanarConfig& config);

  const TargetObservation& process(const cv::Mat& gray, Seconds t, std::optional<double> expected_distance_m) override;
  void reset() override;

  const planar::PlanarResult& last_result() const { return result_; }
  const planar::PlanarObjectLocalizer& localizer() const { return localizer_; }

 private:
  planar::PlanarObjectLocalizer localizer_;
  planar::PlanarResult result_;
  TargetObservation observation_;
  std::optional<Seconds> last_t_;
  bool retry_without_distance_ = false;
  int confirming_ = -1;  // frames a retried detection at an implausible distance has been tracked; -1: none
};

// Reads a target's template, refusing a target without one with its id in the message.
planar::PlanarTemplate load_target_template(const PlanarTarget& target, const planar::PlanarConfig& config);

}  // namespace labo::fusion
