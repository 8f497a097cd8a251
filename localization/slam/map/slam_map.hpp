#pragma once
// SlamMap: keyframes and map points behind one reader-writer lock. The mapper is the only writer
// (it may therefore read without the lock); the tracker and status() read under a shared lock.
#include <map>
#include <mutex>
#include <optional>
#include <shared_mutex>
#include <unordered_map>
#include <vector>

#include "localization/slam/map/keyframe.hpp"
#include "localization/slam/optimize/sim3.hpp"

namespace labo::slam {

// A closed loop: the measured similarity S_current * S_loop^-1 between two keyframes, kept so that
// later pose-graph optimisations keep the loop closed (saved with the map).
struct LoopEdge {
  int current = -1;
  int loop = -1;
  Similarity3 measured;
};

// A map correction (loop closure or bundle adjustment) as the tracker needs it: every keyframe's
// correction G_k (corrected map coordinates = G_k * old coordinates, for what is attached to
// keyframe k; identity for keyframes that did not move). The tracker carries its pose over with its
// reference keyframe's correction. `generation` counts corrections.
struct MapCorrection {
  int generation = 0;
  std::vector<Similarity3> keyframe_correction;
};

class SlamMap {
 public:
  std::shared_mutex& mutex() const { return mutex_; }

  // Writers (hold the unique lock).
  int add_keyframe(Keyframe kf);  // returns its id
  PointId add_point(MapPoint p);   // returns its id; links its observations into the keyframes
  void add_observation(PointId id, int keyframe, int feature);
  void remove_observation(PointId id, int keyframe);
  void remove_point(PointId id);
  // `drop` is the same physical point as `keep` (found again after a loop): its observations move to
  // `keep` (unless that keyframe already observes `keep`) and `drop` is removed.
  void merge_point(PointId keep, PointId drop);
  void add_loop_edge(const LoopEdge& edge) { loop_edges_.push_back(edge); }
  // Records a correction (the keyframe poses and points were already written) and bumps the generation.
  void record_correction(std::vector<Similarity3> keyframe_correction);
  // The map's estimate of gravity's direction (unit "down" vector in map coordinates), from the
  // keyframes' IMU attitudes; refined by global adjustments, held by local ones.
  void set_down_map(const Eigen::Vector3d& down) { down_map_ = down.normalized(); }
  void clear();

  // Readers.
  const std::vector<Keyframe>& keyframes() const { return keyframes_; }
  std::vector<Keyframe>& keyframes_mutable() { return keyframes_; }
  const std::unordered_map<PointId, MapPoint>& points() const { return points_; }
  std::unordered_map<PointId, MapPoint>& points_mutable() { return points_; }
  const MapPoint* point(PointId id) const {
    const auto it = points_.find(id);
    return it == points_.end() ? nullptr : &it->second;
  }
  // Keyframes sharing the most points with `keyframe`, best first (at most `count`).
  std::vector<int> covisible(int keyframe, int count) const;
  // The same with the number of shared points: (keyframe, shared), best first.
  std::vector<std::pair<int, int>> covisible_counts(int keyframe, int count) const;
  // Keyframes nearest to a camera pose (centre distance, looking roughly the same way).
  std::vector<int> nearest(const Eigen::Isometry3d& T_cam_map, int count) const;
  const std::vector<LoopEdge>& loop_edges() const { return loop_edges_; }
  int generation() const { return generation_; }
  // Corrections newer than `generation`, oldest first (the last few are kept).
  std::vector<const MapCorrection*> corrections_since(int generation) const;
  const std::optional<Eigen::Vector3d>& down_map() const { return down_map_; }
  PointId next_point_id() const { return next_point_id_; }
  void set_next_point_id(PointId id) { next_point_id_ = id; }

 private:
  mutable std::shared_mutex mutex_;
  std::vector<Keyframe> keyframes_;
  std::unordered_map<PointId, MapPoint> points_;
  PointId next_point_id_ = 0;
  std::vector<LoopEdge> loop_edges_;
  std::optional<Eigen::Vector3d> down_map_;
  std::vector<MapCorrection> corrections_;  // the most recent few
  int generation_ = 0;
};

}  // namespace labo::slam
