#pragma once
// FrameTracker: one frame against the map, from a pose prior. The local map is the points of the
// keyframes nearest to the prior and of those covisible with the last reference keyframe. A coarse
// stage searches a few points (coarsest levels first) over a wide radius and updates the pose; a
// fine stage searches every point in view over a tight radius; the final pose is solved from the
// fine matches with Huber weights and a chi-square outlier gate. Quality = found / attempted.
#include <unordered_set>
#include <vector>

#include "localization/slam/map/slam_map.hpp"
#include "localization/slam/match/projection_matcher.hpp"
#include "localization/slam/optimize/pose_optimizer.hpp"

namespace labo::slam {

struct TrackerSettings {
  int levels = 4;
  double level_scale = 1.5;
  int max_points_searched = 800;
  int coarse_points = 60;
  double coarse_radius_px = 30.0;
  double fine_radius_px = 6.0;
  int max_hamming = 50;
  int local_keyframes = 10;
};

struct TrackOutcome {
  bool pose_valid = false;
  Eigen::Isometry3d T_cam_map = Eigen::Isometry3d::Identity();
  int found = 0;
  int attempted = 0;
  double mean_depth = 0;
  int reference_keyframe = -1;     // the keyframe sharing most matched points
  int reference_shared = 0;        // how many
  int reference_points = 0;        // points of that keyframe
  std::vector<std::pair<int, PointId>> matches;  // (feature, point), inliers only
  int map_generation = 0;          // of the map the local map was read from
  SearchBreakdown search;          // the fine stage's misses
  int pose_outliers = 0;           // matched, then rejected by the pose update
};

class FrameTracker {
 public:
  FrameTracker(const IdealCamera& camera, const TrackerSettings& settings);
  TrackOutcome track(const SlamMap& map, const FrameFeatures& frame, const FeatureGrid& grid,
                     const Eigen::Isometry3d& prior_T_cam_map, int last_reference_keyframe, bool coarse_stage);

 private:
  void collect_candidates(const SlamMap& map, const Eigen::Isometry3d& T, int reference_keyframe);
  int solve(const std::vector<SearchMatch>& matches, const FrameFeatures& frame, Eigen::Isometry3d& T);

  const IdealCamera& camera_;
  TrackerSettings settings_;
  ProjectionMatcher matcher_;
  std::vector<SearchCandidate> candidates_;
  std::unordered_set<PointId> seen_;
  std::vector<int> in_view_, coarse_;
  std::vector<SearchMatch> matches_;
  std::vector<PoseObservation> observations_;
  std::vector<std::pair<int, int>> reference_count_;
};

}  // namespace labo::slam
