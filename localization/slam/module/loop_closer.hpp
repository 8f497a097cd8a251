#pragma once
// LoopCloser: when a new keyframe sees again a place mapped long before, the drift accumulated
// around the loop (pose and, monocular, scale) is measured and removed.
//
// 1. Detection: keyframes at least `min_gap_s` older than the new one are ranked by small-image
//    similarity (as for relocalization); the best few are matched by descriptor against the new
//    keyframe's mapped features. Each match of a new keyframe's point with an old point is a 3D-3D
//    pair; RANSAC over similarities (optimize/sim3_solver) gives G, old = G * drifted, and a guided
//    search of the old points with the corrected pose must confirm it.
// 2. Correction: a Sim(3) pose graph over all keyframes (edges between neighbours in time, between
//    strongly covisible keyframes, earlier loops, and the new loop edge), the loop keyframe and every
//    keyframe before it fixed; each point moves with its reference keyframe's correction.
// 3. Fusion: the old points are searched in the new keyframe and its covisible neighbours; a
//    duplicate (a new point on the same feature) is merged into the old point.
// The mapper runs it after each keyframe; it computes without the map lock (the mapper is the only
// writer) and writes the result under one unique lock, with the per-keyframe corrections recorded in
// the map so that the tracker carries its pose over consistently.
#include <optional>
#include <vector>

#include "localization/slam/camera/ideal_camera.hpp"
#include "localization/slam/map/slam_map.hpp"
#include "localization/slam/match/projection_matcher.hpp"
#include "localization/slam/module/loop_report.hpp"

namespace labo::slam {

struct LoopSettings {
  bool enabled = true;
  double min_gap_s = 20.0;         // a loop keyframe is at least this much older
  int candidates = 3;              // old keyframes tried per new keyframe
  int max_hamming = 50;
  int min_inliers = 20;            // Sim(3) RANSAC inliers
  int min_confirmed = 40;          // old points found again in the new keyframe with the corrected pose
  int covisibility_edge_points = 40;  // shared points for a pose-graph edge
  double loop_edge_weight = 10.0;     // loop edges against edges measured with the drift
  // Below these the loop is consistent already: points are fused but poses are left alone.
  double min_rotation_deg = 0.3;
  double min_translation_ratio = 0.005;  // of the keyframe's median scene depth
  double min_scale_change = 0.015;
  int fuse_keyframes = 10;         // covisible keyframes searched for duplicates
  int levels = 4;
  double level_scale = 1.5;
};


class LoopCloser {
 public:
  LoopCloser(const IdealCamera& camera, SlamMap& map, const LoopSettings& settings);
  // Called by the mapper (the only writer) once keyframe `kf` is in the map and adjusted.
  LoopReport process(int kf);

 private:
  struct Detection {
    int loop = -1;
    Similarity3 old_from_current;  // G
    int inliers = 0, confirmed = 0;
  };
  std::optional<Detection> detect(int kf) const;
  std::optional<Detection> try_candidate(int kf, int loop) const;
  std::vector<int> old_neighbourhood(int loop, double before_t) const;
  // A point is old when its reference keyframe is older than before_t.
  bool is_old_point(const MapPoint& p, double before_t) const;
  // The old points of the loop keyframe's old neighbourhood, as search candidates.
  std::vector<SearchCandidate> old_points(int loop, double before_t) const;
  void correct(int kf, const Detection& d);
  int fuse(int kf, const Detection& d);
  double sigma(int level) const;

  const IdealCamera& camera_;
  SlamMap& map_;
  LoopSettings settings_;
  mutable ProjectionMatcher matcher_;
};

}  // namespace labo::slam
