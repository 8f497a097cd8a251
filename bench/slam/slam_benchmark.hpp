#pragma once
// The SLAM benchmark: runs SlamSystem over ground-truth flights (the synthetic room, the simulated lab)
// and reports trajectory errors, timing, relocalization time and where tracking was lost near the
// instrument.
#include <functional>
#include <iosfwd>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "bench/slam/bench_flights.hpp"
#include "bench/slam/trajectory_metrics.hpp"
#include "localization/slam/slam_system.hpp"

namespace labo::bench {

struct FlightReport {
  std::string name;
  int frames = 0;
  int tracked_frames = 0;  // good or dodgy
  int good_frames = 0;
  int lost_frames = 0;     // after initialization
  double initialized_at_s = -1;
  int initialization_attempts = 0;
  std::optional<TrajectoryErrors> errors;           // every tracked frame, as tracked (online)
  std::optional<TrajectoryErrors> keyframe_errors;  // the final map's keyframe poses (ORB-SLAM's convention)
  std::vector<double> ate_by_10s_m;                 // online error along the flight (whole-flight alignment)
  std::vector<PosePair> trajectory;                 // tracked poses with ground truth
  std::vector<PosePair> keyframe_trajectory;        // the final map's keyframes with ground truth
  double tracking_ms_median = 0, tracking_ms_p95 = 0;          // wall time
  double tracking_cpu_ms_median = 0, tracking_cpu_ms_p95 = 0;  // thread CPU time
  double mapping_ms_per_keyframe_median = 0, mapping_ms_per_keyframe_max = 0;
  int keyframes = 0, map_points = 0, global_ba_runs = 0;
  int loops_detected = 0, loops_corrected = 0, points_fused = 0;
  int clearance_skips = 0;
  double loop_ms_max = 0;
  double loop_search_ms_median = 0, loop_search_ms_p95 = 0;
  std::optional<double> relocalization_s;  // view back -> tracking good again
  std::optional<double> lost_at_distance_m;  // approach: first lost frame's distance to the panel
  double closest_tracked_distance_m = 0;     // approach: closest good/dodgy frame
  // Over all frames tracked against the map: points attempted, found, and why the others were not.
  long long attempted = 0, found = 0;
  struct {
    long long no_feature = 0, too_far = 0, ambiguous = 0, taken = 0, pose_outliers = 0;
  } misses;
};

struct BenchOptions {
  slam::MappingMode mode = slam::MappingMode::Synchronous;
  double tour_duration_s = 120.0;
  bool add_lens_distortion = true;
};

// Frame i of a flight, 8-bit grey (the synthetic room or the simulated lab).
using FlightRenderer = std::function<cv::Mat(const Flight& flight, std::size_t i)>;

// The IMU's roll and pitch given to SLAM with every frame, as drone/sim's SensorModel makes them: the
// true attitude of the body plus a constant offset per axis (drawn once per flight) and white noise
// per sample. Defaults: the simulated lab's noise (0.09 deg) and the offset a flat trim before
// take-off leaves (0.1 x 0.6 deg, docs/state-estimation.md).
struct ImuAttitudeModel {
  double noise_rad = 0.0015;
  double offset_rad = 0.001;
  unsigned seed = 0;
};

// trace (optional): one line per frame that is not Good or adds a keyframe. imu: the attitude given
// with each frame (none: frames alone; SLAM uses it only when settings.gravity_sigma_deg > 0).
FlightReport run_flight(const FlightRenderer& render, const Flight& flight, const PinholeCamera& camera,
                        const slam::SlamSettings& settings, std::ostream* trace = nullptr,
                        const std::optional<ImuAttitudeModel>& imu = std::nullopt);

}  // namespace labo::bench
