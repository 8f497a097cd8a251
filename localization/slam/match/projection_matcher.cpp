#include "localization/slam/match/projection_matcher.hpp"

#include <algorithm>
#include <cmath>

namespace labo::slam {

ProjectionMatcher::ProjectionMatcher(const IdealCamera& camera, int levels, double level_scale)
    : camera_(camera), levels_(levels), log_scale_(std::log(level_scale)) {
  double s = 1.0;
  for (int l = 0; l < levels; ++l) {
    scales_.push_back(s);
    s *= level_scale;
  }
}

int ProjectionMatcher::project_candidates(std::vector<SearchCandidate>& candidates,
                                          const Eigen::Isometry3d& T_cam_map) const {
  int in_view = 0;
  for (SearchCandidate& c : candidates) {
    const Eigen::Vector3d p = T_cam_map * c.p_map;
    c.in_view = false;
    if (p.z() <= 1e-3 || !camera_.visible(p, 4.0)) continue;
    const double distance = p.norm();
    // Seen at reference_level from reference_distance: closer makes it bigger, i.e. a coarser level.
    const double level = c.reference_level + std::log(c.reference_distance / distance) / log_scale_;
    // Far outside the pyramid's range the descriptor cannot match: not attempted.
    if (level < -1.5 || level > levels_ + 0.5) continue;
    c.predicted_level = std::clamp(static_cast<int>(std::lround(level)), 0, levels_ - 1);
    c.px = *camera_.project(p);
    c.in_view = true;
    ++in_view;
  }
  return in_view;
}

void ProjectionMatcher::search(const std::vector<SearchCandidate>& candidates, const std::vector<int>& which,
                               const FrameFeatures& frame, const FeatureGrid& grid, double radius_px,
                               int min_level, int max_hamming, std::vector<SearchMatch>& matches) {
  matches.clear();
  feature_owner_.assign(frame.size(), -1);
  breakdown_ = {};
  for (int ci : which) {
    const SearchCandidate& c = candidates[static_cast<std::size_t>(ci)];
    if (!c.in_view) continue;
    const int lo = std::max(min_level, c.predicted_level - 1);
    const int hi = std::min(levels_ - 1, c.predicted_level + 1);
    if (lo > hi) continue;
    ++breakdown_.searched;
    grid.query(c.px, radius_px * scales_[static_cast<std::size_t>(c.predicted_level)], lo, hi, frame, nearby_);
    int best = 257, second = 257, best_feature = -1;
    for (int fi : nearby_) {
      const int d = hamming(c.descriptor, frame.descriptors[static_cast<std::size_t>(fi)]);
      if (d < best) {
        second = best;
        best = d;
        best_feature = fi;
      } else if (d < second) {
        second = d;
      }
    }
    if (best_feature < 0) {
      ++breakdown_.no_feature;
      continue;
    }
    if (best > max_hamming) {
      ++breakdown_.too_far;
      continue;
    }
    // Ratio test only when the runner-up is also a plausible match: repeated texture.
    if (second <= max_hamming && best > 0.85 * second) {
      ++breakdown_.ambiguous;
      continue;
    }
    int& owner = feature_owner_[static_cast<std::size_t>(best_feature)];
    if (owner >= 0) {
      ++breakdown_.taken;  // this point or the feature's previous owner goes without
      if (matches[static_cast<std::size_t>(owner)].distance <= best) continue;
      matches[static_cast<std::size_t>(owner)] = {ci, best_feature, best};
      continue;
    }
    owner = static_cast<int>(matches.size());
    matches.push_back({ci, best_feature, best});
  }
}

}  // namespace labo::slam
