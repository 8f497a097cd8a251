#pragma once
// MapInitializer: automatic two-view initialization (no key presses, as tum_ardrone's autoInit
// drives it during take-off). The first textured frame becomes the reference; its features are
// followed frame to frame by windowed descriptor search; once the median displacement is large
// enough the two-view reconstruction is tried on every frame. The reference is replaced (a retry)
// when too many tracks are lost or after a timeout.
#include <optional>
#include <string>
#include <vector>

#include "core/time.hpp"
#include "localization/slam/feature/frame_features.hpp"
#include "localization/slam/initialize/two_view_geometry.hpp"

namespace labo::slam {

struct InitializerSettings {
  double min_parallax_px = 20.0;
  double timeout_s = 3.0;
  double search_radius_px = 30.0;
  int max_hamming = 60;
  TwoViewSettings geometry;
};

struct InitialMap {
  FrameFeatures reference;
  Seconds reference_t = 0;
  std::vector<std::pair<int, int>> matches;  // (reference feature, current feature), one per point
  std::vector<Eigen::Vector3d> points;       // reference camera frame, median depth 1
  Eigen::Isometry3d T_current_reference;
  TwoViewModel model = TwoViewModel::Essential;
};

class MapInitializer {
 public:
  MapInitializer(const IdealCamera& camera, const InitializerSettings& settings);
  void reset();
  // Returns the initial map when this frame completes initialization. `reason` says why not.
  std::optional<InitialMap> add_frame(const FrameFeatures& frame, const FeatureGrid& grid, Seconds t);
  const std::string& reason() const { return reason_; }
  int attempts() const { return attempts_; }
  bool has_reference() const { return has_reference_; }

 private:
  void set_reference(const FrameFeatures& frame, Seconds t);

  const IdealCamera& camera_;
  InitializerSettings settings_;
  bool has_reference_ = false;
  FrameFeatures reference_;
  Seconds reference_t_ = 0;
  std::vector<Eigen::Vector2d> last_px_;  // where each reference feature was last seen
  std::vector<int> current_match_;        // its feature in the current frame, -1 if not found
  std::vector<int> nearby_;
  std::string reason_ = "waiting for a textured frame";
  int attempts_ = 0;
};

}  // namespace labo::slam
