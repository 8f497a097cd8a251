#pragma once
// SlamMap: keyframes and map points behind one reader-writer lock. The mapper is the only writer
// (it may therefore read without the lock); the tracker and status() read under a shared lock.
#include <map>
#include <mutex>
#include <shared_mutex>
#include <unordered_map>
#include <vector>

#include "localization/slam/map/keyframe.hpp"

namespace labo::slam {

class SlamMap {
 public:
  std::shared_mutex& mutex() const { return mutex_; }

  // Writers (hold the unique lock).
  int add_keyframe(Keyframe kf);  // returns its id
  PointId add_point(MapPoint p);   // returns its id; links its observations into the keyframes
  void add_observation(PointId id, int keyframe, int feature);
  void remove_observation(PointId id, int keyframe);
  void remove_point(PointId id);
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
  // Keyframes nearest to a camera pose (centre distance, looking roughly the same way).
  std::vector<int> nearest(const Eigen::Isometry3d& T_cam_map, int count) const;
  PointId next_point_id() const { return next_point_id_; }
  void set_next_point_id(PointId id) { next_point_id_ = id; }

 private:
  mutable std::shared_mutex mutex_;
  std::vector<Keyframe> keyframes_;
  std::unordered_map<PointId, MapPoint> points_;
  PointId next_point_id_ = 0;
};

}  // namespace labo::slam
