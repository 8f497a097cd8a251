#include "localization/slam/module/keyframe_policy.hpp"

namespace labo::slam {

bool keyframe_eligible(const KeyframeCandidate& c, const SlamSettings& s) {
  if (c.state == TrackingState::Good) return true;
  if (c.state != TrackingState::Dodgy) return false;
  // Dodgy only because the map is small: the frame finds most of what it searches (ratio Good) but
  // fewer than min_found_good points exist to be found. A map initialized from a few tens of points
  // is in this state right after take-off; refusing its keyframes would leave it at two keyframes
  // until tracking is lost (docs/slam.md). Test "keyframe policy: a frame Dodgy only for the map's
  // size may add a keyframe".
  const double ratio = c.attempted > 0 ? static_cast<double>(c.found) / c.attempted : 0.0;
  if (ratio >= s.quality_good) return true;
  // Dodgy by ratio but holding hundreds of points: a fast approach (docs/slam.md, lab-inspect; test
  // "keyframe policy: Dodgy frames holding many points, as configured").
  return s.keyframe_min_points_dodgy > 0 && c.found >= s.keyframe_min_points_dodgy;
}

bool keyframe_needed(const KeyframeCandidate& c, const SlamSettings& s) {
  // Far enough from every keyframe, relative to the scene depth ...
  if (c.nearest_keyframe_distance > s.keyframe_distance_ratio * c.mean_depth) return true;
  // ... or the view has turned away from the reference keyframe (rotation, approach) ...
  if (c.reference_points > 0 && c.reference_shared < s.keyframe_overlap_ratio * c.reference_points) return true;
  // ... or the reference keyframe is too small for the overlap rule: holding fewer than
  // min_found_good / overlap points, it would only fire once the frame is no longer Good (and Good
  // frames are what may add keyframes), so a small initial map would never grow.
  return c.reference_points > 0 && c.reference_points < s.min_found_good / s.keyframe_overlap_ratio;
}

}  // namespace labo::slam
