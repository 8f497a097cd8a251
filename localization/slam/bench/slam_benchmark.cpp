#include "localization/slam/bench/slam_benchmark.hpp"

#include <algorithm>
#include <ostream>

namespace labo::slam {
namespace {

double percentile(std::vector<double> v, double q) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return v[static_cast<std::size_t>(std::min<double>(v.size() - 1, q * (v.size() - 1) + 0.5))];
}

}  // namespace

FlightReport run_flight(const SyntheticRoom& room, const Flight& flight, const PinholeCamera& camera, MappingMode mode,
                        std::ostream* trace) {
  SlamSettings settings;
  settings.mapping_mode = mode;
  SlamSystem slam(camera, settings);
  FlightReport report;
  report.name = flight.name;
  std::vector<PosePair> pairs;
  std::vector<double> tracking_ms;
  const cv::Mat black = cv::Mat::zeros(camera.height(), camera.width(), CV_8U);
  bool initialized = false;
  for (std::size_t i = 0; i < flight.frames.size(); ++i) {
    const FlightFrame& f = flight.frames[i];
    const cv::Mat image = f.covered ? black : room.render(f.T_world_cam, static_cast<unsigned>(i));
    const SlamResult r = slam.track(image, f.t);
    ++report.frames;
    if (trace && (r.state != TrackingState::Good || r.keyframe_added)) {
      *trace << flight.name << " t=" << f.t << " " << to_string(r.state) << " found " << r.points_found << "/" << r.points_attempted
             << (r.keyframe_added ? " +KF" : "") << " " << r.tracking_ms << " ms " << r.reason << "\n";
    }
    if (!initialized && r.state != TrackingState::Initializing) {
      initialized = true;
      report.initialized_at_s = f.t;
    }
    if (initialized) tracking_ms.push_back(r.tracking_ms);
    const double distance = (flight.target - f.T_world_cam.translation()).norm();
    if (r.T_cam_map) {
      ++report.tracked_frames;
      report.good_frames += r.state == TrackingState::Good ? 1 : 0;
      pairs.push_back({f.t, r.T_cam_map->inverse(), f.T_world_cam});
      if (flight.name == "approach") {
        report.closest_tracked_distance_m = report.closest_tracked_distance_m == 0 ? distance : std::min(report.closest_tracked_distance_m, distance);
      }
      if (flight.view_returns_at >= 0 && f.t >= flight.view_returns_at && !report.relocalization_s && r.state == TrackingState::Good) {
        report.relocalization_s = f.t - flight.view_returns_at;
      }
    } else if (initialized) {
      ++report.lost_frames;
      if (flight.name == "approach" && !report.lost_at_distance_m) report.lost_at_distance_m = distance;
    }
  }
  slam.wait_for_mapping();
  report.errors = trajectory_errors(pairs);
  report.tracking_ms_median = percentile(tracking_ms, 0.5);
  report.tracking_ms_p95 = percentile(tracking_ms, 0.95);
  const MappingStatistics mapping = slam.mapping_statistics();
  report.mapping_ms_per_keyframe_median = percentile(mapping.keyframe_ms, 0.5);
  report.mapping_ms_per_keyframe_max = percentile(mapping.keyframe_ms, 1.0);
  report.global_ba_runs = mapping.global_ba_runs;
  const SlamStatus status = slam.status();
  report.keyframes = status.keyframes;
  report.map_points = status.map_points;
  return report;
}

}  // namespace labo::slam
