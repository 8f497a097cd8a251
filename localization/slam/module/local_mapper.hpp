#pragma once
// LocalMapper: everything that happens when a keyframe arrives. It adds the keyframe, re-measures
// the neighbours' points in it, creates new points by epipolar search against its neighbours and
// triangulation, runs a local bundle adjustment (the keyframe and its most covisible neighbours,
// their points; other observers fixed) and removes outliers. When idle it runs a global adjustment.
//
// Threaded mode: a worker thread consumes the queue; tracking only waits for the map lock while
// results are written. Synchronous mode: enqueue() processes the keyframe inline with the same code,
// and runs the global adjustment every `global_ba_every` keyframes, so lockstep runs repeat exactly.
#include <atomic>
#include <condition_variable>
#include <deque>
#include <mutex>
#include <thread>

#include "localization/slam/camera/ideal_camera.hpp"
#include "localization/slam/map/slam_map.hpp"
#include "localization/slam/match/patch_aligner.hpp"
#include "localization/slam/match/projection_matcher.hpp"
#include "localization/slam/module/loop_closer.hpp"

namespace labo::slam {

struct MapperSettings {
  bool threaded = true;
  int levels = 4;
  double level_scale = 1.5;
  int local_ba_keyframes = 5;
  int local_ba_iterations = 10;
  int global_ba_iterations = 10;
  int triangulation_neighbours = 5;
  bool global_ba = true;
  int global_ba_every = 5;        // synchronous mode
  int global_ba_max_keyframes = 200;
  int global_ba_fixed_keyframes = 1;  // the first n keyframes hold the gauge (2 also fixes the scale)
  bool cull_points = true;            // remove points that keep being missed when re-measured
  double new_point_clearance_px = 0;  // no new point at a corner this close (x level scale) to a mapped one
  double min_parallax_deg = 0.5;
  int max_hamming = 50;
  bool patch_refinement = true;  // re-measured and newly matched corners aligned to sub-pixel
  double gravity_sigma_rad = 0;  // > 0: the keyframes' IMU attitudes as a prior of every adjustment
  LoopSettings loop;
};

struct MapperStats {
  int keyframes_processed = 0;
  int local_ba_runs = 0;
  int global_ba_runs = 0;
  int points_created = 0;
  int observations_removed = 0;
  int clearance_skips = 0;      // corners not triangulated: a mapped corner next to them
  int points_culled = 0;
  double last_keyframe_ms = 0;  // wall time of the last keyframe's processing (measurement only)
  std::vector<double> keyframe_ms;
  std::vector<LoopReport> loops;  // every detected loop, corrected or not
  std::vector<double> loop_ms;    // wall time of each correction (pose graph, points, fusion)
  std::vector<double> loop_search_ms;  // wall time of the loop search of each keyframe
};

class LocalMapper {
 public:
  LocalMapper(const IdealCamera& camera, SlamMap& map, const MapperSettings& settings);
  ~LocalMapper();
  LocalMapper(const LocalMapper&) = delete;
  LocalMapper& operator=(const LocalMapper&) = delete;

  // The keyframe's point_of_feature holds the tracker's associations (kNoPoint elsewhere).
  void enqueue(Keyframe keyframe);
  int queued() const;
  // Two-view bundle adjustment of a fresh map (called inline, before tracking starts).
  void adjust_initial_map();
  void wait_idle();
  MapperStats stats() const;

 private:
  void worker();
  void process(Keyframe keyframe);
  void remeasure(int kf, const std::vector<int>& neighbours);
  void triangulate_new_points(int kf, const std::vector<int>& neighbours);
  void adjust(const std::vector<int>& free_keyframes, bool global, int max_iterations);
  void global_adjustment();
  void close_loops(int kf);
  void carry_over_corrections(Keyframe& keyframe) const;
  double sigma(int level) const;
  // Per feature of `kf`: 1 when a feature within new_point_clearance_px x its level scale (any level)
  // holds a map point - the same corner found on another pyramid level, already mapped.
  std::vector<char> near_mapped(const Keyframe& kf, const FeatureGrid& grid) const;
  // Sub-pixel position of `p_map` in keyframe `target`, by aligning the patch of `source`'s feature
  // (distorted level-0 pixel), or empty (no pyramid, no convergence).
  std::optional<Eigen::Vector2d> align(const Keyframe& source, int source_feature, const Eigen::Vector3d& p_map,
                                       const Keyframe& target, int target_feature);
  // Moves a keyframe feature to a refined distorted level-0 position (caller holds the unique lock).
  void move_feature(Keyframe& kf, int feature, const Eigen::Vector2d& image_px) const;

  const IdealCamera& camera_;
  SlamMap& map_;
  MapperSettings settings_;
  ProjectionMatcher matcher_;
  PatchAligner aligner_;
  LoopCloser loop_closer_;
  mutable std::mutex mutex_;
  std::condition_variable wake_, idle_;
  std::deque<Keyframe> queue_;
  bool busy_ = false;
  bool stop_ = false;
  bool global_pending_ = false;
  std::atomic<bool> abort_{false};
  MapperStats stats_;
  std::thread thread_;
};

}  // namespace labo::slam
