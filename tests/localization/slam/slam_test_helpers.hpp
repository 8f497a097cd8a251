#pragma once
// Shared fixtures for the SLAM tests: the synthetic room seen by the AR.Drone front camera, and a
// runner that feeds a flight's frames to a SlamSystem.
#include <algorithm>
#include <cmath>
#include <vector>

#include "localization/slam/bench/bench_flights.hpp"
#include "localization/slam/bench/synthetic_room.hpp"
#include "localization/slam/bench/trajectory_metrics.hpp"
#include "localization/slam/slam_system.hpp"

namespace labo::slam::testing {

// Where a camera ray (world frame) leaves the room's box.
inline Eigen::Vector3d hit_wall(const SyntheticRoomSpec& room, const Eigen::Vector3d& origin, const Eigen::Vector3d& dir) {
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
  std::vector<PosePair> tracked;
  std::vector<SlamResult> results;
};

inline RunResult run(SlamSystem& slam, const SyntheticRoom& room, const std::vector<FlightFrame>& frames) {
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

inline std::vector<FlightFrame> first_seconds(const Flight& flight, double seconds) {
  std::vector<FlightFrame> out;
  for (const auto& f : flight.frames) {
    if (f.t < seconds) out.push_back(f);
  }
  return out;
}

}  // namespace labo::slam::testing
