#include "localization/slam/initialize/map_initializer.hpp"

#include <algorithm>

namespace labo::slam {
namespace {
constexpr int kMinReferenceFeatures = 150;
}

MapInitializer::MapInitializer(const IdealCamera& camera, const InitializerSettings& settings)
    : camera_(camera), settings_(settings) {}

void MapInitializer::reset() {
  has_reference_ = false;
  reason_ = "waiting for a textured frame";
}

void MapInitializer::set_reference(const FrameFeatures& frame, Seconds t) {
  if (static_cast<int>(frame.size()) < kMinReferenceFeatures) {
    has_reference_ = false;
    reason_ = "too few corners for a reference frame (" + std::to_string(frame.size()) + ")";
    return;
  }
  reference_ = frame;
  reference_t_ = t;
  last_px_.resize(frame.size());
  for (std::size_t i = 0; i < frame.size(); ++i) last_px_[i] = frame.features[i].px;
  current_match_.assign(frame.size(), -1);
  has_reference_ = true;
  ++attempts_;
  reason_ = "initializing: move the camera (translation)";
}

std::optional<InitialMap> MapInitializer::add_frame(const FrameFeatures& frame, const FeatureGrid& grid, Seconds t) {
  if (!has_reference_ || t - reference_t_ > settings_.timeout_s) {
    set_reference(frame, t);
    return std::nullopt;
  }
  // Follow every reference feature that is still alive; a current feature goes to one reference
  // feature only (the closest in descriptor space).
  std::vector<int> owner(frame.size(), -1);
  std::vector<int> owner_distance(frame.size(), 257);
  int alive = 0;
  for (std::size_t i = 0; i < reference_.size(); ++i) {
    current_match_[i] = -1;
    if (last_px_[i].x() < -1e8) continue;
    const int level = reference_.features[i].level;
    grid.query(last_px_[i], settings_.search_radius_px, std::max(0, level - 1), level + 1, frame, nearby_);
    int best = 257, best_f = -1;
    for (int f : nearby_) {
      const int d = hamming(reference_.descriptors[i], frame.descriptors[static_cast<std::size_t>(f)]);
      if (d < best) {
        best = d;
        best_f = f;
      }
    }
    if (best_f < 0 || best > settings_.max_hamming || owner_distance[static_cast<std::size_t>(best_f)] <= best) {
      last_px_[i] = Eigen::Vector2d::Constant(-1e9);  // lost for good
      continue;
    }
    if (owner[static_cast<std::size_t>(best_f)] >= 0) {
      const auto loser = static_cast<std::size_t>(owner[static_cast<std::size_t>(best_f)]);
      current_match_[loser] = -1;
      last_px_[loser] = Eigen::Vector2d::Constant(-1e9);
      --alive;
    }
    owner[static_cast<std::size_t>(best_f)] = static_cast<int>(i);
    owner_distance[static_cast<std::size_t>(best_f)] = best;
    current_match_[i] = best_f;
    ++alive;
  }
  std::vector<Eigen::Vector2d> a, b;
  std::vector<int> ref_index;
  std::vector<double> displacement;
  for (std::size_t i = 0; i < reference_.size(); ++i) {
    if (current_match_[i] < 0) continue;
    last_px_[i] = frame.features[static_cast<std::size_t>(current_match_[i])].px;
    a.push_back(reference_.features[i].px);
    b.push_back(last_px_[i]);
    ref_index.push_back(static_cast<int>(i));
    displacement.push_back((b.back() - a.back()).norm());
  }
  if (alive < settings_.geometry.min_points) {
    reason_ = "initialization lost its tracks: retrying";
    set_reference(frame, t);
    return std::nullopt;
  }
  std::nth_element(displacement.begin(), displacement.begin() + static_cast<long>(displacement.size() / 2), displacement.end());
  if (displacement[displacement.size() / 2] < settings_.min_parallax_px) {
    reason_ = "initializing: waiting for parallax";
    return std::nullopt;
  }
  TwoViewOutcome outcome = reconstruct_two_views(camera_, a, b, settings_.geometry);
  if (!outcome.reconstruction) {
    reason_ = "initializing: " + outcome.reason;
    return std::nullopt;
  }
  TwoViewReconstruction& r = *outcome.reconstruction;
  std::vector<double> depths;
  for (const auto& p : r.points) depths.push_back(p.z());
  std::nth_element(depths.begin(), depths.begin() + static_cast<long>(depths.size() / 2), depths.end());
  const double scale = 1.0 / depths[depths.size() / 2];
  InitialMap map;
  map.reference = reference_;
  map.reference_t = reference_t_;
  map.T_current_reference = r.T_second_first;
  map.T_current_reference.translation() *= scale;
  map.model = r.model;
  for (std::size_t k = 0; k < r.match_index.size(); ++k) {
    const int ri = ref_index[static_cast<std::size_t>(r.match_index[k])];
    map.matches.emplace_back(ri, current_match_[static_cast<std::size_t>(ri)]);
    map.points.push_back(r.points[k] * scale);
  }
  reason_.clear();
  return map;
}

}  // namespace labo::slam
