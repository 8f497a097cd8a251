#include "bench/slam/bench_flights.hpp"

#include <algorithm>
#include <cmath>

#include "core/frames.hpp"

namespace labo::bench {

namespace {

constexpr double kFps = 30.0;

double smoothstep(double x) {
  x = std::clamp(x, 0.0, 1.0);
  return x * x * (3 - 2 * x);
}

Eigen::Isometry3d camera_pose(const Eigen::Vector3d& body, double yaw, double pitch = 0, double roll = 0) {
  return make_pose(body, yaw, pitch, roll) * T_body_cam_front();
}

// Take-off manoeuvre: hover 1 s at `start`, climb by `climb_m` over 2 s, hover 0.5 s.
Eigen::Vector3d takeoff(const Eigen::Vector3d& start, double climb_m, Seconds t) {
  return start + Eigen::Vector3d(0, 0, climb_m * smoothstep((t - 1.0) / 2.0));
}

}  // namespace

Flight tour_flight(Seconds duration_s) {
  Flight f;
  f.name = "tour";
  const Eigen::Vector3d center(4, 3, 1.0), start(5.2, 3, 1.0);
  const Seconds tour_start = 3.5, loops = 2.0;
  const Seconds loop_s = (duration_s - tour_start) / loops;
  const Seconds cover_from = 0.6 * duration_s, cover_to = cover_from + 1.0;
  f.view_returns_at = cover_to;
  for (int i = 0; i < static_cast<int>(duration_s * kFps); ++i) {
    const Seconds t = i / kFps;
    Eigen::Vector3d p = takeoff(start, 0.4, t);
    double yaw = 0;
    if (t > tour_start) {
      const double phi = 2 * M_PI * (t - tour_start) / loop_s;
      const Eigen::Vector3d on_loop(start.x() + 1.8 * (std::cos(phi) - 1),
                                    center.y() + 1.3 * std::sin(phi), 1.4 + 0.25 * std::sin(2 * M_PI * (t - tour_start) / 17.0));
      const double blend = smoothstep((t - tour_start) / 3.0);
      p = (1 - blend) * p + blend * on_loop;
      yaw = phi;
    }
    const double pitch = 0.03 * std::sin(1.3 * t), roll = 0.02 * std::sin(0.9 * t + 1);
    f.frames.push_back({t, camera_pose(p, yaw, pitch, roll), t >= cover_from && t < cover_to});
  }
  return f;
}

Flight yaw_flight() {
  Flight f;
  f.name = "yaw";
  const Eigen::Vector3d start(4, 3, 1.0);
  const Seconds turn_start = 4.0, turn_s = 18.0;
  for (int i = 0; i < static_cast<int>((turn_start + turn_s + 2.0) * kFps); ++i) {
    const Seconds t = i / kFps;
    const double yaw = 2 * M_PI * smoothstep((t - turn_start) / turn_s);
    f.frames.push_back({t, camera_pose(takeoff(start, 0.4, t), yaw), false});
  }
  return f;
}

Flight approach_flight(const Eigen::Vector3d& panel_center) {
  Flight f;
  f.name = "approach";
  f.target = panel_center;
  const double cam_offset = 0.2;  // body centre to camera along x
  const double start_distance = 3.3, end_distance = 0.8;
  const Eigen::Vector3d start(panel_center.x() - start_distance - cam_offset, panel_center.y(), panel_center.z() - 0.3);
  const Seconds approach_start = 4.0, approach_s = 20.0;
  for (int i = 0; i < static_cast<int>((approach_start + approach_s + 3.0) * kFps); ++i) {
    const Seconds t = i / kFps;
    Eigen::Vector3d p = takeoff(start, 0.3, t);
    p.x() += (start_distance - end_distance) * smoothstep((t - approach_start) / approach_s);
    f.frames.push_back({t, camera_pose(p, 0.0, 0.02 * std::sin(1.1 * t)), false});
  }
  return f;
}

}  // namespace labo::bench
