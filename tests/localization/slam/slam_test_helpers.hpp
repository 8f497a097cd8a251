#pragma once
// Shared fixtures for the SLAM tests: the synthetic room seen by the AR.Drone front camera, a
// runner that feeds a flight's frames to a SlamSystem, and a mapper fed keyframes with true poses.
#include <algorithm>
#include <cmath>
#include <vector>

#include "bench/slam/bench_flights.hpp"
#include "bench/slam/synthetic_room.hpp"
#include "bench/slam/trajectory_metrics.hpp"
#include "localization/slam/feature/feature_extractor.hpp"
#include "localization/slam/module/local_mapper.hpp"
#include "localization/slam/slam_system.hpp"

namespace labo::slam::testing {

// Where a camera ray (world frame) leaves the room's box.
inline Eigen::Vector3d hit_wall(const bench::SyntheticRoomSpec& room, const Eigen::Vector3d& origin, const Eigen::Vector3d& dir) {
  double nearest = 1e9;
  for (int axis = 0; axis < 3; ++axis) {
    if (std::abs(dir[axis]) < 1e-12) continue;
    const double wall = dir[axis] > 0 ? room.max_corner[axis] : room.min_corner[axis];
    nearest = std::min(nearest, (wall - origin[axis]) / dir[axis]);
  }
  return origin + nearest * dir;
}

inline SlamSettings synchronous() {
  SlamSettings s;
  s.mapping_mode = MappingMode::Synchronous;
  return s;
}

struct RunResult {
  std::vector<bench::PosePair> tracked;
  std::vector<SlamResult> results;
};

inline RunResult run(SlamSystem& slam, const bench::SyntheticRoom& room, const std::vector<bench::FlightFrame>& frames) {
  RunResult out;
  for (std::size_t i = 0; i < frames.size(); ++i) {
    const SlamResult r = slam.track(room.render(frames[i].T_world_cam, static_cast<unsigned>(i)), frames[i].t);
    if (r.T_cam_map) out.tracked.push_back({frames[i].t, r.T_cam_map->inverse(), frames[i].T_world_cam});
    out.results.push_back(r);
  }
  return out;
}

// Fraction of the frames after initialization that have a pose.
inline double tracked_fraction_after_init(const RunResult& run) {
  int after = 0, tracked = 0;
  bool initialized = false;
  for (const auto& r : run.results) {
    initialized = initialized || r.state != TrackingState::Initializing;
    if (!initialized) continue;
    ++after;
    tracked += r.T_cam_map ? 1 : 0;
  }
  return after > 0 ? static_cast<double>(tracked) / after : 0.0;
}

inline std::vector<bench::FlightFrame> first_seconds(const bench::Flight& flight, double seconds) {
  std::vector<bench::FlightFrame> out;
  for (const auto& f : flight.frames) {
    if (f.t < seconds) out.push_back(f);
  }
  return out;
}

// A LocalMapper in synchronous mode on the synthetic room, without global adjustment, loop closure
// or patch alignment (the mapper's own steps alone), with a first keyframe whose every other corner
// is mapped exactly on the walls. Further keyframes are rendered at given poses and enqueued without
// associations: each is re-measured, triangulated and adjusted locally.
struct SeededMapper {
  explicit SeededMapper(const MapperSettings& mapper_settings)
      : real(PinholeCamera::ardrone2_front()), camera(real), room(real), extractor(camera, ExtractorSettings{}),
        mapper(camera, map, mapper_settings) {}

  static MapperSettings settings() {
    MapperSettings s;
    s.threaded = false;
    s.global_ba = false;
    s.loop.enabled = false;
    s.patch_refinement = false;
    return s;
  }

  // Keyframe 0 at its true pose, every other corner mapped where its ray meets a wall.
  void seed(const Eigen::Isometry3d& T_world_cam, unsigned noise_seed) {
    Keyframe first;
    first.T_cam_map = T_world_cam.inverse();
    extractor.extract(room.render(T_world_cam, noise_seed), first.frame);
    const int k0 = map.add_keyframe(std::move(first));
    const Keyframe& kf0 = map.keyframes()[static_cast<std::size_t>(k0)];
    for (std::size_t i = 0; i < kf0.frame.size(); i += 2) {
      const Feature& f = kf0.frame.features[i];
      MapPoint p;
      p.p_map = hit_wall(room.spec(), T_world_cam.translation(), T_world_cam.linear() * camera.bearing(f.px));
      p.descriptor = kf0.frame.descriptors[i];
      p.observations = {{k0, static_cast<int>(i)}};
      p.reference_keyframe = k0;
      p.reference_level = f.level;
      p.reference_distance = (p.p_map - T_world_cam.translation()).norm();
      map.add_point(std::move(p));
    }
  }

  // A keyframe rendered at T_world_cam, given the pose T_cam_map (the true one unless a test
  // perturbs it), no associations.
  Keyframe keyframe(const Eigen::Isometry3d& T_world_cam, const Eigen::Isometry3d& T_cam_map, Seconds t, unsigned noise_seed) {
    Keyframe kf;
    kf.t = t;
    kf.T_cam_map = T_cam_map;
    extractor.extract(room.render(T_world_cam, noise_seed), kf.frame);
    kf.point_of_feature.assign(kf.frame.size(), kNoPoint);
    return kf;
  }

  PinholeCamera real;
  IdealCamera camera;
  bench::SyntheticRoom room;
  FeatureExtractor extractor;
  SlamMap map;
  LocalMapper mapper;
};

}  // namespace labo::slam::testing
