#pragma once
// Guided search of map points in a frame: each point is projected with a pose guess, its pyramid
// level predicted from the distance at which it was first seen, and the frame's features near the
// projection (radius scaled by the level) are compared by Hamming distance. A feature goes to the
// closest point that claims it.
#include <Eigen/Geometry>
#include <algorithm>
#include <vector>

#include "localization/slam/camera/ideal_camera.hpp"
#include "localization/slam/feature/frame_features.hpp"
#include "localization/slam/map/keyframe.hpp"

namespace labo::slam {

struct SearchCandidate {
  PointId id = kNoPoint;
  Eigen::Vector3d p_map;
  Descriptor descriptor;
  int reference_level = 0;
  double reference_distance = 1.0;
  int reference_keyframe = -1;
  int reference_feature = -1;  // the point's feature in its reference keyframe (its patch), -1: none
  // Filled by project_candidates():
  Eigen::Vector2d px = Eigen::Vector2d::Zero();
  int predicted_level = 0;
  bool in_view = false;
};

inline SearchCandidate candidate_of(const MapPoint& p) {
  SearchCandidate c;
  c.id = p.id;
  c.p_map = p.p_map;
  c.descriptor = p.descriptor;
  c.reference_level = p.reference_level;
  c.reference_distance = p.reference_distance;
  c.reference_keyframe = p.reference_keyframe;
  c.reference_feature = p.observed_by(p.reference_keyframe);
  return c;
}

// Why the searched points were not matched (diagnosis: what the tracker sees).
struct SearchBreakdown {
  int searched = 0;
  int no_feature = 0;  // no feature of a plausible level near the projection
  int too_far = 0;     // the closest descriptor beyond max_hamming
  int ambiguous = 0;   // a runner-up almost as close (ratio test)
  int taken = 0;       // the feature went to a closer point
};

struct SearchMatch {
  int candidate = -1;
  int feature = -1;
  int distance = 256;
};

class ProjectionMatcher {
 public:
  ProjectionMatcher(const IdealCamera& camera, int levels, double level_scale);

  // Projects every candidate; returns how many are in view.
  int project_candidates(std::vector<SearchCandidate>& candidates, const Eigen::Isometry3d& T_cam_map) const;

  // Searches the in-view candidates listed in `which` (indices into candidates) within
  // radius_px * scale^level, over levels [predicted - 1, predicted + 1] clamped to [min_level, ..].
  // Appends to `matches` (cleared first). Features already claimed in `feature_taken` (size of the
  // frame, -1 = free) are skipped unless this candidate matches them better.
  void search(const std::vector<SearchCandidate>& candidates, const std::vector<int>& which,
              const FrameFeatures& frame, const FeatureGrid& grid, double radius_px, int min_level,
              int max_hamming, std::vector<SearchMatch>& matches);

  // Of the last search() call.
  const SearchBreakdown& breakdown() const { return breakdown_; }

  double level_scale(int level) const { return scales_[static_cast<std::size_t>(std::clamp(level, 0, levels_ - 1))]; }

 private:
  const IdealCamera& camera_;
  int levels_;
  double log_scale_;
  std::vector<double> scales_;
  std::vector<int> nearby_;
  std::vector<int> feature_owner_;  // match index owning each feature
  SearchBreakdown breakdown_;
};

}  // namespace labo::slam
