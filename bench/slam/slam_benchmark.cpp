#include "bench/slam/slam_benchmark.hpp"

#include <algorithm>
#include <ostream>
#include <random>

#include "core/frames.hpp"

namespace labo::bench {

using slam::GravityMeasurement;
using slam::LoopReport;
using slam::MappingStatistics;
using slam::SlamResult;
using slam::SlamSettings;
using slam::SlamStatus;
using slam::SlamSystem;
using slam::TrackingState;
using slam::gravity_down_in_camera;

namespace {

double percentile(std::vector<double> v, double q) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return v[static_cast<std::size_t>(std::min<double>(v.size() - 1, q * (v.size() - 1) + 0.5))];
}

}  // namespace

FlightReport run_flight(const FlightRenderer& render, const Flight& flight, const PinholeCamera& camera,
                        const SlamSettings& settings, std::ostream* trace, const std::optional<ImuAttitudeModel>& imu) {
  SlamSystem slam(camera, settings);
  std::mt19937 imu_rng(imu ? imu->seed : 0u);
  std::normal_distribution<double> unit_normal(0.0, 1.0);
  const double roll_offset = imu ? imu->offset_rad * unit_normal(imu_rng) : 0.0;
  const double pitch_offset = imu ? imu->offset_rad * unit_normal(imu_rng) : 0.0;
  const Eigen::Isometry3d T_cam_body = T_body_cam_front().inverse();
  FlightReport report;
  report.name = flight.name;
  std::vector<PosePair> pairs;
  std::vector<double> tracking_ms, tracking_cpu_ms;
  const cv::Mat black = cv::Mat::zeros(camera.height(), camera.width(), CV_8U);
  bool initialized = false;
  for (std::size_t i = 0; i < flight.frames.size(); ++i) {
    const FlightFrame& f = flight.frames[i];
    const cv::Mat image = f.covered ? black : render(flight, i);
    std::optional<GravityMeasurement> gravity;
    if (imu) {
      const Eigen::Vector3d ypr = ypr_from_rotation((f.T_world_cam * T_cam_body).linear());
      const double roll = ypr.z() + roll_offset + imu->noise_rad * unit_normal(imu_rng);
      const double pitch = ypr.y() + pitch_offset + imu->noise_rad * unit_normal(imu_rng);
      gravity = GravityMeasurement{f.t, gravity_down_in_camera(roll, pitch, T_body_cam_front())};
    }
    const SlamResult r = slam.track(image, f.t, std::nullopt, gravity);
    ++report.frames;
    if (trace && (r.state != TrackingState::Good || r.keyframe_added)) {
      *trace << flight.name << " t=" << f.t << " " << to_string(r.state) << " found " << r.points_found << "/" << r.points_attempted
             << (r.keyframe_added ? " +KF" : "") << " " << r.tracking_ms << " ms (cpu " << r.tracking_cpu_ms << ") " << r.reason;
      const SlamResult::Misses& m = r.misses;
      if (r.points_attempted > 0) {
        *trace << " [misses: no feature " << m.no_feature << ", too far " << m.too_far << ", ambiguous " << m.ambiguous
               << ", taken " << m.taken << ", pose outliers " << m.pose_outliers << "]";
      }
      if (flight.target) *trace << " [" << (*flight.target - f.T_world_cam.translation()).norm() << " m from the target]";
      *trace << "\n";
    }
    if (!initialized && r.state != TrackingState::Initializing) {
      initialized = true;
      report.initialized_at_s = f.t;
    }
    if (initialized) {
      tracking_ms.push_back(r.tracking_ms);
      tracking_cpu_ms.push_back(r.tracking_cpu_ms);
    }
    const double distance = flight.target ? (*flight.target - f.T_world_cam.translation()).norm() : 0.0;
    report.attempted += r.points_attempted;
    report.found += r.points_found;
    report.misses.no_feature += r.misses.no_feature;
    report.misses.too_far += r.misses.too_far;
    report.misses.ambiguous += r.misses.ambiguous;
    report.misses.taken += r.misses.taken;
    report.misses.pose_outliers += r.misses.pose_outliers;
    if (r.T_cam_map) {
      ++report.tracked_frames;
      report.good_frames += r.state == TrackingState::Good ? 1 : 0;
      pairs.push_back({f.t, r.T_cam_map->inverse(), f.T_world_cam});
      if (flight.target) {
        report.closest_tracked_distance_m = report.closest_tracked_distance_m == 0 ? distance : std::min(report.closest_tracked_distance_m, distance);
      }
      if (flight.view_returns_at >= 0 && f.t >= flight.view_returns_at && !report.relocalization_s && r.state == TrackingState::Good) {
        report.relocalization_s = f.t - flight.view_returns_at;
      }
    } else if (initialized) {
      ++report.lost_frames;
      if (flight.target && !report.lost_at_distance_m) report.lost_at_distance_m = distance;
    }
  }
  slam.wait_for_mapping();
  report.errors = trajectory_errors(pairs);
  report.ate_by_10s_m = windowed_ate_m(pairs, 10.0);
  report.trajectory = std::move(pairs);
  report.tracking_ms_median = percentile(tracking_ms, 0.5);
  report.tracking_ms_p95 = percentile(tracking_ms, 0.95);
  report.tracking_cpu_ms_median = percentile(tracking_cpu_ms, 0.5);
  report.tracking_cpu_ms_p95 = percentile(tracking_cpu_ms, 0.95);
  const MappingStatistics mapping = slam.mapping_statistics();
  report.mapping_ms_per_keyframe_median = percentile(mapping.keyframe_ms, 0.5);
  report.mapping_ms_per_keyframe_max = percentile(mapping.keyframe_ms, 1.0);
  report.global_ba_runs = mapping.global_ba_runs;
  report.loops_detected = mapping.loops_detected;
  report.loops_corrected = mapping.loops_corrected;
  report.points_fused = mapping.points_fused;
  report.clearance_skips = mapping.clearance_skips;
  report.loop_ms_max = percentile(mapping.loop_ms, 1.0);
  report.loop_search_ms_median = percentile(mapping.loop_search_ms, 0.5);
  report.loop_search_ms_p95 = percentile(mapping.loop_search_ms, 0.95);
  if (trace) {
    for (const LoopReport& l : mapping.loops) {
      *trace << flight.name << " loop: keyframe " << l.current << " -> " << l.loop << (l.corrected ? " corrected" : " consistent")
             << ", inliers " << l.inliers << ", confirmed " << l.confirmed << ", moved " << l.correction_translation << " map units, "
             << l.correction_rotation_deg << " deg, scale " << l.correction_scale << ", fused " << l.points_fused << "\n";
    }
  }
  const SlamStatus status = slam.status();
  report.keyframes = status.keyframes;
  report.map_points = status.map_points;
  std::vector<PosePair> keyframe_pairs;
  for (std::size_t k = 0; k < status.keyframe_times.size(); ++k) {
    const Seconds t = status.keyframe_times[k];
    const auto truth = std::lower_bound(flight.frames.begin(), flight.frames.end(), t,
                                        [](const FlightFrame& f, Seconds value) { return f.t < value; });
    if (truth != flight.frames.end() && truth->t == t) keyframe_pairs.push_back({t, status.keyframes_T_map_cam[k], truth->T_world_cam});
  }
  report.keyframe_errors = trajectory_errors(keyframe_pairs);
  report.keyframe_trajectory = std::move(keyframe_pairs);
  return report;
}

}  // namespace labo::bench
