#include "localization/slam/module/frame_tracker.hpp"

#include <algorithm>
#include <map>

namespace labo::slam {

FrameTracker::FrameTracker(const IdealCamera& camera, const TrackerSettings& settings)
    : camera_(camera), settings_(settings), matcher_(camera, settings.levels, settings.level_scale), aligner_(camera) {}

int FrameTracker::pyramid_slot(const Keyframe& kf) {
  if (kf.pyramid.empty()) return -1;
  int& slot = slot_of_keyframe_[static_cast<std::size_t>(kf.id)];
  if (slot >= 0) return slot;
  if (pyramid_count_ == pyramids_.size()) pyramids_.emplace_back();
  pyramids_[pyramid_count_] = kf.pyramid;  // headers only: keyframe images are never written again
  slot = static_cast<int>(pyramid_count_++);
  return slot;
}

void FrameTracker::collect_candidates(const SlamMap& map, const Eigen::Isometry3d& T, int reference_keyframe) {
  candidates_.clear();
  patches_.clear();
  seen_.clear();
  for (std::size_t i = 0; i < pyramid_count_; ++i) {
    for (cv::Mat& level : pyramids_[i]) level.release();  // let go of keyframes no longer local
  }
  pyramid_count_ = 0;
  slot_of_keyframe_.assign(map.keyframes().size(), -1);
  std::vector<int> kfs = map.nearest(T, settings_.local_keyframes);
  if (reference_keyframe >= 0 && reference_keyframe < static_cast<int>(map.keyframes().size())) {
    kfs.push_back(reference_keyframe);
    for (int k : map.covisible(reference_keyframe, settings_.local_keyframes / 2)) kfs.push_back(k);
  }
  for (int k : kfs) {
    for (PointId id : map.keyframes()[static_cast<std::size_t>(k)].point_of_feature) {
      if (id == kNoPoint || !seen_.insert(id).second) continue;
      const MapPoint* p = map.point(id);
      if (!p) continue;
      candidates_.push_back(candidate_of(*p));
      PatchRef patch;
      const SearchCandidate& c = candidates_.back();
      if (settings_.patch_refinement && c.reference_feature >= 0 && c.reference_keyframe >= 0 &&
          c.reference_keyframe < static_cast<int>(map.keyframes().size())) {
        const Keyframe& source = map.keyframes()[static_cast<std::size_t>(c.reference_keyframe)];
        patch.slot = pyramid_slot(source);
        patch.T_cam_map = source.T_cam_map;
        const Feature& f = source.frame.features[static_cast<std::size_t>(c.reference_feature)];
        patch.image_px = f.image_px.cast<double>();
        patch.level = f.level;
      }
      patches_.push_back(patch);
    }
  }
}

void FrameTracker::refine_matches(const FrameFeatures& frame, const std::vector<cv::Mat>& pyramid, const Eigen::Isometry3d& T) {
  match_image_px_.clear();
  match_refined_.assign(matches_.size(), 0);
  for (std::size_t i = 0; i < matches_.size(); ++i) {
    const SearchMatch& m = matches_[i];
    const Feature& f = frame.features[static_cast<std::size_t>(m.feature)];
    match_image_px_.push_back(f.image_px.cast<double>());
    const PatchRef& patch = patches_[static_cast<std::size_t>(m.candidate)];
    if (!settings_.patch_refinement || patch.slot < 0 || pyramid.empty()) continue;
    const PatchSource source{&pyramids_[static_cast<std::size_t>(patch.slot)], patch.T_cam_map, patch.image_px, patch.level};
    const auto aligned = aligner_.align(source, candidates_[static_cast<std::size_t>(m.candidate)].p_map, pyramid, T,
                                        match_image_px_.back());
    if (!aligned) continue;
    match_image_px_.back() = aligned->image_px;
    match_refined_[i] = 1;
  }
}

int FrameTracker::solve(const std::vector<SearchMatch>& matches, const FrameFeatures& frame, Eigen::Isometry3d& T, bool refined,
                        const std::optional<GravityPrior>& gravity) {
  observations_.clear();
  for (std::size_t i = 0; i < matches.size(); ++i) {
    const SearchMatch& m = matches[i];
    const Feature& f = frame.features[static_cast<std::size_t>(m.feature)];
    const Eigen::Vector2d px = refined && match_refined_[i] ? camera_.ideal_from_image(match_image_px_[i].x(), match_image_px_[i].y()) : f.px;
    observations_.push_back({candidates_[static_cast<std::size_t>(m.candidate)].p_map, px, matcher_.level_scale(f.level), true});
  }
  return optimize_pose(camera_, observations_, T, {}, gravity);
}

void FrameTracker::read_local_map(const SlamMap& map, const Eigen::Isometry3d& T, int reference_keyframe, TrackOutcome& out) {
  std::shared_lock lock(map.mutex());
  out.map_generation = map.generation();
  collect_candidates(map, T, reference_keyframe);
  // Unlocked on return: candidates are copies, the mapper may proceed.
}

void FrameTracker::coarse_search(const FrameFeatures& frame, const FeatureGrid& grid, const std::optional<GravityPrior>& gravity,
                                 Eigen::Isometry3d& T) {
  // The points predicted at the coarsest levels, searched wide.
  coarse_.clear();
  for (int level = settings_.levels - 1; level >= 0 && static_cast<int>(coarse_.size()) < settings_.coarse_points; --level) {
    for (std::size_t i = 0; i < candidates_.size() && static_cast<int>(coarse_.size()) < settings_.coarse_points; ++i) {
      if (candidates_[i].in_view && candidates_[i].predicted_level == level) coarse_.push_back(static_cast<int>(i));
    }
  }
  matcher_.search(candidates_, coarse_, frame, grid, settings_.coarse_radius_px, 0, settings_.max_hamming, matches_);
  Eigen::Isometry3d T_coarse = T;
  if (matches_.size() >= 10 && solve(matches_, frame, T_coarse, false, gravity) >= 8) {
    T = T_coarse;
    matcher_.project_candidates(candidates_, T);
  }
}

void FrameTracker::fine_search(const FrameFeatures& frame, const FeatureGrid& grid, bool after_coarse, TrackOutcome& out) {
  in_view_.clear();
  for (std::size_t i = 0; i < candidates_.size(); ++i) {
    if (candidates_[i].in_view) in_view_.push_back(static_cast<int>(i));
  }
  if (static_cast<int>(in_view_.size()) > settings_.max_points_searched) {
    // Evenly thinned: keeps the spread over the image.
    const double step = static_cast<double>(in_view_.size()) / settings_.max_points_searched;
    for (int i = 0; i < settings_.max_points_searched; ++i) in_view_[static_cast<std::size_t>(i)] = in_view_[static_cast<std::size_t>(i * step)];
    in_view_.resize(static_cast<std::size_t>(settings_.max_points_searched));
  }
  out.attempted = static_cast<int>(in_view_.size());
  matcher_.search(candidates_, in_view_, frame, grid, settings_.fine_radius_px, 0, settings_.max_hamming, matches_);
  if (matches_.size() < 20 && !after_coarse) {
    // The prior was off by more than the fine radius: widen once.
    matcher_.search(candidates_, in_view_, frame, grid, 3.0 * settings_.fine_radius_px, 0, settings_.max_hamming, matches_);
  }
  out.search = matcher_.breakdown();
}

bool FrameTracker::update_pose(const FrameFeatures& frame, const std::vector<cv::Mat>& pyramid,
                               const std::optional<GravityPrior>& gravity, Eigen::Isometry3d& T, TrackOutcome& out) {
  refine_matches(frame, pyramid, T);
  const int inliers = solve(matches_, frame, T, true, gravity);
  out.pose_outliers = static_cast<int>(matches_.size()) - inliers;
  if (inliers < 6) return false;
  out.pose_valid = true;
  out.T_cam_map = T;
  out.found = inliers;
  double depth_sum = 0;
  for (std::size_t i = 0; i < matches_.size(); ++i) {
    if (!observations_[i].inlier) continue;
    const SearchCandidate& c = candidates_[static_cast<std::size_t>(matches_[i].candidate)];
    out.matches.emplace_back(matches_[i].feature, c.id);
    out.match_image_px.push_back(match_image_px_[i]);
    out.refined += match_refined_[i];
    depth_sum += (T * c.p_map).z();
  }
  out.mean_depth = depth_sum / std::max(1, inliers);
  return true;
}

void FrameTracker::find_reference_keyframe(const SlamMap& map, TrackOutcome& out) const {
  // The keyframe observing most of the matched points.
  std::shared_lock lock(map.mutex());
  std::map<int, int> shared;
  for (const auto& [f, id] : out.matches) {
    if (const MapPoint* p = map.point(id)) {
      for (const Observation& o : p->observations) ++shared[o.keyframe];
    }
  }
  for (const auto& [kf, n] : shared) {
    if (n > out.reference_shared) {
      out.reference_shared = n;
      out.reference_keyframe = kf;
    }
  }
  if (out.reference_keyframe >= 0) {
    for (PointId id : map.keyframes()[static_cast<std::size_t>(out.reference_keyframe)].point_of_feature) {
      out.reference_points += map.point(id) ? 1 : 0;
    }
  }
}

TrackOutcome FrameTracker::track(const SlamMap& map, const FrameFeatures& frame, const FeatureGrid& grid,
                                 const std::vector<cv::Mat>& pyramid, const Eigen::Isometry3d& prior, int last_reference_keyframe, bool coarse_stage,
                                 const std::optional<GravityPrior>& gravity) {
  TrackOutcome out;
  Eigen::Isometry3d T = prior;
  read_local_map(map, T, last_reference_keyframe, out);
  matcher_.project_candidates(candidates_, T);
  if (coarse_stage) coarse_search(frame, grid, gravity, T);
  fine_search(frame, grid, coarse_stage, out);
  if (matches_.size() < 6) return out;
  if (!update_pose(frame, pyramid, gravity, T, out)) return out;
  find_reference_keyframe(map, out);
  return out;
}

}  // namespace labo::slam
