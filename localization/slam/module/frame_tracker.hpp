#pragma once
// FrameTracker: one frame against the map, from a pose prior. The local map is the points of the
// keyframes nearest to the prior and of those covisible with the last reference keyframe. A coarse
// stage searches a few points (coarsest levels first) over a wide radius and updates the pose; a
// fine stage searches every point in view over a tight radius; the final pose is solved from the
// fine matches with Huber weights and a chi-square outlier gate. Quality = found / attempted.
// Before the final pose, each fine match's corner is refined to sub-pixel by aligning the point's
// warped patch from its reference keyframe (match/patch_aligner): the pose and, through the
// keyframes the tracker adds, the map are measured at those positions.
#include <unordered_set>
#include <vector>

#include "localization/slam/map/slam_map.hpp"
#include "localization/slam/match/patch_aligner.hpp"
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
  bool patch_refinement = true;  // sub-pixel alignment of the fine matches (match/patch_aligner)
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
  std::vector<Eigen::Vector2d> match_image_px;   // per match: where it was measured (distorted level-0 px)
  int refined = 0;                               // matches measured by patch alignment
  int map_generation = 0;          // of the map the local map was read from
  SearchBreakdown search;          // the fine stage's misses
  int pose_outliers = 0;           // matched, then rejected by the pose update
};

class FrameTracker {
 public:
  FrameTracker(const IdealCamera& camera, const TrackerSettings& settings);
  // pyramid: the frame's (as the features were found on it), for the patch alignment. `gravity`:
  // the IMU's attitude at this frame as a prior of every pose update (none: reprojection only).
  TrackOutcome track(const SlamMap& map, const FrameFeatures& frame, const FeatureGrid& grid, const std::vector<cv::Mat>& pyramid,
                     const Eigen::Isometry3d& prior_T_cam_map, int last_reference_keyframe, bool coarse_stage,
                     const std::optional<GravityPrior>& gravity = std::nullopt);

 private:
  // The steps of track(), in order.
  // The candidates: the local map's points, copied under the map's lock.
  void read_local_map(const SlamMap& map, const Eigen::Isometry3d& T, int reference_keyframe, TrackOutcome& out);
  // A few points from the coarsest levels over a wide radius; their pose replaces T when it holds.
  void coarse_search(const FrameFeatures& frame, const FeatureGrid& grid, const std::optional<GravityPrior>& gravity,
                     Eigen::Isometry3d& T);
  // Every point in view (evenly thinned to max_points_searched) over the tight radius.
  void fine_search(const FrameFeatures& frame, const FeatureGrid& grid, bool after_coarse, TrackOutcome& out);
  // The fine matches refined to sub-pixel, the pose solved from them; false when too few inliers.
  bool update_pose(const FrameFeatures& frame, const std::vector<cv::Mat>& pyramid, const std::optional<GravityPrior>& gravity,
                   Eigen::Isometry3d& T, TrackOutcome& out);
  void find_reference_keyframe(const SlamMap& map, TrackOutcome& out) const;

  void collect_candidates(const SlamMap& map, const Eigen::Isometry3d& T, int reference_keyframe);
  int solve(const std::vector<SearchMatch>& matches, const FrameFeatures& frame, Eigen::Isometry3d& T, bool refined,
            const std::optional<GravityPrior>& gravity);
  // Keeps (a copy of the header of) a keyframe's pyramid for this frame; returns its slot or -1.
  int pyramid_slot(const Keyframe& kf);
  void refine_matches(const FrameFeatures& frame, const std::vector<cv::Mat>& pyramid, const Eigen::Isometry3d& T);

  // A candidate's patch source, copied under the map lock (parallel to candidates_).
  struct PatchRef {
    int slot = -1;
    Eigen::Isometry3d T_cam_map = Eigen::Isometry3d::Identity();
    Eigen::Vector2d image_px = Eigen::Vector2d::Zero();
    int level = 0;
  };

  const IdealCamera& camera_;
  TrackerSettings settings_;
  ProjectionMatcher matcher_;
  PatchAligner aligner_;
  std::vector<PatchRef> patches_;
  std::vector<std::vector<cv::Mat>> pyramids_;  // reused: slots [0, pyramid_count_)
  std::size_t pyramid_count_ = 0;
  std::vector<int> slot_of_keyframe_;
  std::vector<Eigen::Vector2d> match_image_px_;  // per fine match: refined or the corner's
  std::vector<char> match_refined_;
  std::vector<SearchCandidate> candidates_;
  std::unordered_set<PointId> seen_;
  std::vector<int> in_view_, coarse_;
  std::vector<SearchMatch> matches_;
  std::vector<PoseObservation> observations_;
  std::vector<std::pair<int, int>> reference_count_;
};

}  // namespace labo::slam
