#include "bench/planar/sequence_bench.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <stdexcept>
#include <functional>
#include <map>
#include <string>
#include <utility>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "bench/frame_timing.hpp"
#include "bench/planar/h264_roundtrip.hpp"
#include "bench/planar/lab_sequences.hpp"
#include "localization/planar/planar_localizer.hpp"
#include "localization/planar/pose/planar_pose_filter.hpp"
#include "bench/planar/synthetic_scene.hpp"

namespace labo::bench {

namespace {

constexpr double kFps = 30.0;
constexpr double kPi = 3.14159265358979323846;

using Sequence = PlanarSequence;

double percentile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<std::size_t>(q * static_cast<double>(v.size())))];
}

void add_noise(cv::Mat& frame, cv::RNG& rng, double sigma) {
  cv::Mat noise(frame.size(), CV_16SC1), wide;
  rng.fill(noise, cv::RNG::NORMAL, 0, sigma);
  frame.convertTo(wide, CV_16S);
  wide += noise;
  wide.convertTo(frame, CV_8U);
}

// Renders a sequence from a camera path (camera position and look-at target in the object frame,
// roll) and per-frame image effects. The sensor noise is seeded by `noise_name`'s hash plus
// `noise_seed` (by default the sequence's own name, seed 0).
Sequence render_sequence(const std::string& name, const PlanarViewRenderer& renderer, const PanelModel& panel, int frames,
                         const std::function<Eigen::Isometry3d(int)>& pose_at,
                         const std::function<void(int, cv::Mat&)>& effect, double min_visible, bool bottom = false,
                         const std::string& noise_name = "", int noise_seed = 0) {
  Sequence s;
  s.name = name;
  s.panel = panel;
  s.bottom_camera = bottom;
  cv::RNG rng(static_cast<std::uint64_t>(std::hash<std::string>{}(noise_name.empty() ? name : noise_name)) +
              static_cast<std::uint64_t>(noise_seed));
  for (int i = 0; i < frames; ++i) {
    const Eigen::Isometry3d T = pose_at(i);
    cv::Mat frame = renderer.render(panel.image, panel.width_m, panel.height_m, T);
    add_noise(frame, rng, 2.0);
    s.in_view.push_back(visible_fraction(renderer.camera(), panel, T) >= min_visible);
    if (effect) effect(i, frame);
    s.frames.push_back(frame);
    s.truth.push_back(T);
  }
  return s;
}

Eigen::Isometry3d facing(double x, double y, double distance, double look_dx = 0, double look_dy = 0, double roll = 0) {
  return look_at_object(Eigen::Vector3d(x, y, -distance), Eigen::Vector3d(x * 0.7 + look_dx, y * 0.7 + look_dy, 0), roll);
}

std::vector<Sequence> make_sequences(const planar::PlanarConfig& config, const PanelModel& panel, const PanelModel& platform,
                                     const std::string& only, int h264_kbps, int h264_seeds) {
  const PinholeCamera front = PinholeCamera::ardrone2_front();
  const PinholeCamera bottom = PinholeCamera::ardrone2_bottom();
  const PlanarViewRenderer front_renderer(front, make_clutter_background(cv::Size(1600, 1600), 21), 0.0025);
  const PlanarViewRenderer bottom_renderer(bottom, make_clutter_background(cv::Size(1600, 1600), 22), 0.0025, 0.02);
  const double mv = config.min_visible_fraction;
  std::vector<Sequence> out;
  const auto wanted = [&](const char* name) { return only.empty() || std::string(name).find(only) != std::string::npos; };

  if (wanted("approach_3m_to_0.5m")) out.push_back(render_sequence("approach_3m_to_0.5m", front_renderer, panel, 180, [](int i) {
    const double a = i / 179.0, d = 3.0 - 2.5 * a;
    return facing(0.15 * std::sin(3 * a), -0.05 + 0.05 * std::cos(2 * a), d, 0, 0, 0.04 * std::sin(5 * a));
  }, nullptr, mv));
  if (wanted("hover_0.8m")) out.push_back(render_sequence("hover_0.8m", front_renderer, panel, 120, [](int i) {
    const double a = i / kFps;
    return facing(0.03 * std::sin(1.3 * a), 0.02 * std::cos(0.9 * a), 0.8 + 0.02 * std::sin(2.1 * a),
                  0.02 * std::sin(1.7 * a), 0.01 * std::cos(1.1 * a), 0.03 * std::sin(2.3 * a));
  }, nullptr, mv));
  if (wanted("lateral_pass_1.5m")) out.push_back(render_sequence("lateral_pass_1.5m", front_renderer, panel, 150, [](int i) {
    const double x = -1.2 + 2.4 * i / 149.0;
    return look_at_object(Eigen::Vector3d(x, 0, -1.5), Eigen::Vector3d(x, 0, 0));
  }, nullptr, mv));
  if (wanted("motion_blur_1.2m")) out.push_back(render_sequence("motion_blur_1.2m", front_renderer, panel, 120, [](int i) {
    return facing(0.25 * std::sin(i / kFps * 2.5), 0, 1.2);
  }, [](int i, cv::Mat& f) {
    // Horizontal blur as long as the image motion during the exposure (up to ~9 px).
    const int len = 1 + static_cast<int>(std::abs(9 * std::cos(i / kFps * 2.5)));
    if (len > 1) {
      cv::Mat k = cv::Mat::ones(1, len, CV_32F) / len;
      cv::filter2D(f, f, -1, k);
    }
  }, mv));
  for (int seed = 0; seed < h264_seeds; ++seed) {
    const std::string name = h264_sequence_name(seed);
    if (!wanted(name.c_str())) continue;
    Sequence h264 = render_sequence(name, front_renderer, panel, 150, [](int i) {
      const double a = i / 149.0;
      return facing(0.1 * std::sin(2 * a), 0.0, 2.5 - 1.8 * a, 0, 0, 0.03 * std::sin(4 * a));
    }, nullptr, mv, false, h264_sequence_name(0), seed);
    h264.frames = h264_roundtrip(h264.frames, drone_stream_settings(cv::Size(front.width(), front.height()), static_cast<int>(kFps), h264_kbps));
    h264.pooled = seed == 0;
    h264.h264_seed = true;
    out.push_back(std::move(h264));
  }
  if (wanted("lighting_change_1.0m")) out.push_back(render_sequence("lighting_change_1.0m", front_renderer, panel, 150, [](int i) {
    return facing(0.05 * std::sin(i / kFps), 0, 1.0);
  }, [](int i, cv::Mat& f) {
    // Gain 1 -> 0.45 -> 1.3 with a bias and a left-to-right light gradient.
    const double a = i / 149.0;
    const double gain = a < 0.5 ? 1.0 - 1.1 * a : 0.45 + 1.7 * (a - 0.5);
    cv::Mat g(f.size(), CV_32F);
    for (int x = 0; x < f.cols; ++x) g.col(x).setTo(gain * (0.8 + 0.4 * x / f.cols));
    cv::Mat ff;
    f.convertTo(ff, CV_32F);
    ff = ff.mul(g) + 20.0 * std::sin(4 * a);
    ff.convertTo(f, CV_8U);
  }, mv));
  if (wanted("corrupted_frames_1.5m")) {
    Sequence drop = render_sequence("corrupted_frames_1.5m", front_renderer, panel, 150, [](int i) {
      return facing(0.3 * std::sin(i / kFps * 0.8), 0.05 * std::cos(i / kFps), 1.5);
    }, nullptr, mv);
    cv::RNG rng(5);
    for (int start : {30, 70, 110}) {
      for (int i = start; i < start + 3; ++i) {  // three frames of garbage, as after a lost H.264 slice
        rng.fill(drop.frames[static_cast<std::size_t>(i)], cv::RNG::UNIFORM, 0, 256);
        drop.in_view[static_cast<std::size_t>(i)] = false;
      }
    }
    out.push_back(std::move(drop));
  }
  if (wanted("lab_renderer_oscilloscope_3m_to_0.6m")) {
    out.push_back(render_lab_approach("lab_renderer_oscilloscope_3m_to_0.6m", mv));
  }
  if (wanted("lab_renderer_platform_1.5m_to_0.3m")) out.push_back(render_lab_platform_pass("lab_renderer_platform_1.5m_to_0.3m", mv));
  if (wanted("platform_descent_bottom_2m_to_0.4m")) out.push_back(render_sequence("platform_descent_bottom_2m_to_0.4m", bottom_renderer, platform, 150, [](int i) {
    const double a = i / 149.0;
    return look_at_object(Eigen::Vector3d(0.1 * std::sin(3 * a), 0.08 * std::cos(2 * a), -(2.0 - 1.6 * a)),
                          Eigen::Vector3d(0.1 * std::sin(3 * a), 0.08 * std::cos(2 * a), 0), 0.5 * a);
  }, nullptr, mv, true));
  return out;
}

struct ErrorSample {
  double range_m, error_percent, error_deg, sigma_deg, filtered_error_deg;
};

double percent_within_2sigma(const std::vector<double>& error_deg, const std::vector<double>& sigma_deg) {
  int within = 0;
  for (std::size_t i = 0; i < error_deg.size(); ++i) within += error_deg[i] <= 2 * sigma_deg[i] ? 1 : 0;
  return error_deg.empty() ? 0.0 : 100.0 * within / static_cast<double>(error_deg.size());
}

constexpr std::pair<double, double> kRangeBins[] = {{0.4, 1.0}, {1.0, 2.0}, {2.0, 3.1}};

RangeBinStats bin_stats(const std::string& tracker, double lo, double hi, const std::vector<ErrorSample>& samples) {
  std::vector<double> pct, deg, sigma, filtered;
  for (const auto& e : samples) {
    if (e.range_m >= lo && e.range_m < hi) {
      pct.push_back(e.error_percent);
      deg.push_back(e.error_deg);
      sigma.push_back(e.sigma_deg);
      filtered.push_back(e.filtered_error_deg);
    }
  }
  return {tracker, lo, hi, static_cast<int>(pct.size()), percentile(pct, 0.5), percentile(pct, 0.95),
          percentile(deg, 0.5), percentile(deg, 0.95), percentile(sigma, 0.5), percent_within_2sigma(deg, sigma),
          percentile(filtered, 0.5), percentile(filtered, 0.95)};
}

std::vector<RangeBinStats> all_bins(const std::string& tracker, const std::vector<ErrorSample>& samples) {
  std::vector<RangeBinStats> bins;
  for (const auto& [lo, hi] : kRangeBins) bins.push_back(bin_stats(tracker, lo, hi, samples));
  return bins;
}

SequenceStats run_one(const Sequence& s, const PanelModel& panel, planar::TrackerKind kind, const planar::PlanarConfig& base_config,
                      const VisionThresholds& vision, std::vector<ErrorSample>& samples,
                      std::vector<FrameRecord>& records) {
  planar::PlanarConfig config = base_config;
  config.tracker = kind;
  const PinholeCamera camera = s.bottom_camera ? PinholeCamera::ardrone2_bottom() : PinholeCamera::ardrone2_front();
  planar::PlanarObjectLocalizer localizer(planar::PlanarTemplate::create(panel.image, panel.width_m, panel.height_m, s.name, config),
                                  camera, planar::PlanarObjectThresholds::from(vision, s.sift_switch_distance_m, s.sift_min_inliers), config);
  SequenceStats st;
  st.sequence = s.name;
  st.tracker = to_string(kind);
  st.min_range_m = 1e9;
  std::vector<double> err_mm, err_pct, err_deg, sigma_deg, filtered_deg, all_ms, tracking_ms, tracking_cpu_ms, detection_ms;
  std::vector<double> refinement_iterations;
  planar::PlanarPoseFilter filter;
  bool had_pose = false;
  int loss_wait = -1;  // frames in view since the last loss, -1 when not recovering
  for (std::size_t i = 0; i < s.frames.size(); ++i) {
    const auto start = std::chrono::steady_clock::now();
    const double start_cpu_ms = thread_cpu_ms();
    const planar::PlanarResult r = localizer.process(s.frames[i], static_cast<double>(i) / kFps);
    const double cpu_ms = thread_cpu_ms() - start_cpu_ms;
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    all_ms.push_back(ms);
    ++st.frames;
    const double range = s.truth[i].translation().norm();
    st.min_range_m = std::min(st.min_range_m, range);
    st.max_range_m = std::max(st.max_range_m, range);
    if (s.in_view[i]) ++st.frames_in_view;
    if (r.state == planar::PlanarState::Tracking) tracking_ms.push_back(ms);
    if (r.state == planar::PlanarState::Tracking) {
      tracking_cpu_ms.push_back(cpu_ms);
      refinement_iterations.push_back(r.refinement_iterations);
    }
    if (r.state != planar::PlanarState::Tracking) detection_ms.push_back(ms);
    if (r.state == planar::PlanarState::Detected) ++st.detections;
    FrameRecord& rec = records.emplace_back();
    rec.sequence = s.name;
    rec.tracker = st.tracker;
    rec.frame = static_cast<int>(i);
    rec.range_m = range;
    rec.in_view = s.in_view[i];
    rec.has_pose = r.has_pose;
    rec.refined = r.pose_refined;
    rec.state = to_string(r.state);
    rec.cpu_ms = cpu_ms;
    Eigen::Matrix3d R_filtered = r.T_cam_object.linear();
    if (r.state == planar::PlanarState::Detected) filter.reset();  // a new detection may be the other IPPE branch
    if (r.has_pose) R_filtered = filter.update(r.T_cam_object.linear(), r.rotation_sigma_rad, static_cast<double>(i) / kFps).R_cam_object;
    if (r.has_pose) {
      const Eigen::AngleAxisd filtered_error(R_filtered * s.truth[i].linear().transpose());
      rec.filtered_rotation_error_deg = filtered_error.axis() * filtered_error.angle() * 180.0 / kPi;
      rec.position_error_m = r.T_cam_object.translation() - s.truth[i].translation();
      const Eigen::AngleAxisd error(r.T_cam_object.linear() * s.truth[i].linear().transpose());
      rec.rotation_error_deg = error.axis() * error.angle() * 180.0 / kPi;
      rec.panel_rotation_error_deg = s.truth[i].linear().transpose() * rec.rotation_error_deg;
      rec.rotation_sigma_deg = r.rotation_sigma_rad * 180.0 / kPi;
    }
    if (r.state == planar::PlanarState::Lost && had_pose) {
      ++st.losses;
      ++st.loss_reasons[to_string(r.reason)];
      loss_wait = 0;
    }
    had_pose = r.has_pose;
    if (r.has_pose) {
      ++st.frames_with_pose;
      if (loss_wait >= 0) {
        ++st.recoveries;
        st.max_recovery_frames = std::max(st.max_recovery_frames, loss_wait);
        loss_wait = -1;
      }
      const double e = (r.T_cam_object.translation() - s.truth[i].translation()).norm();
      const double deg = planar::rotation_angle(r.T_cam_object.linear(), s.truth[i].linear()) * 180.0 / kPi;
      err_mm.push_back(1000 * e);
      err_pct.push_back(100 * e / range);
      err_deg.push_back(deg);
      sigma_deg.push_back(r.rotation_sigma_rad * 180.0 / kPi);
      filtered_deg.push_back(planar::rotation_angle(R_filtered, s.truth[i].linear()) * 180.0 / kPi);
      st.refined_poses += r.pose_refined ? 1 : 0;
      samples.push_back({range, 100 * e / range, deg, sigma_deg.back(), filtered_deg.back()});
      if (100 * e / range > 10 || deg > 10) ++st.gross_errors;
    } else if (s.in_view[i]) {
      ++st.frames_in_view_without_pose;
      if (loss_wait >= 0) ++loss_wait;
    }
  }
  st.median_error_mm = percentile(err_mm, 0.5);
  st.p95_error_mm = percentile(err_mm, 0.95);
  st.median_error_percent = percentile(err_pct, 0.5);
  st.p95_error_percent = percentile(err_pct, 0.95);
  st.median_error_deg = percentile(err_deg, 0.5);
  st.p95_error_deg = percentile(err_deg, 0.95);
  st.median_rotation_sigma_deg = percentile(sigma_deg, 0.5);
  st.median_filtered_error_deg = percentile(filtered_deg, 0.5);
  st.p95_filtered_error_deg = percentile(filtered_deg, 0.95);
  st.rotation_within_2sigma_percent = percent_within_2sigma(err_deg, sigma_deg);
  st.median_frame_ms = percentile(all_ms, 0.5);
  st.median_tracking_ms = percentile(tracking_ms, 0.5);
  st.p95_tracking_ms = percentile(tracking_ms, 0.95);
  st.median_tracking_cpu_ms = percentile(tracking_cpu_ms, 0.5);
  for (double m : detection_ms) st.mean_detection_ms += m / static_cast<double>(detection_ms.size());
  for (double n : refinement_iterations) st.mean_refinement_iterations += n / static_cast<double>(refinement_iterations.size());
  return st;
}

}  // namespace

std::string h264_sequence_name(int seed) {
  const std::string name = "h264_approach_2.5m_to_0.7m";
  return seed == 0 ? name : name + "_seed" + std::to_string(seed);
}

SequenceBenchResult run_sequence_bench(const planar::PlanarConfig& config, const VisionThresholds& vision,
                                       const std::string& only, const std::vector<planar::TrackerKind>& trackers,
                                       int h264_kbps, int h264_seeds) {
  if (h264_kbps <= 0) throw std::invalid_argument("run_sequence_bench: h264_kbps must be positive");
  if (h264_seeds < 1 || h264_seeds > kMaxH264Seeds) {
    throw std::invalid_argument("run_sequence_bench: h264_seeds must be in [1, " + std::to_string(kMaxH264Seeds) + "]");
  }
  SequenceBenchResult result;
  result.renderer = "planar synthetic renderer (localization/planar/synthetic_scene): panel on a textured wall, "
                    "AR.Drone 2.0 front camera with distortion / bottom camera, 2 grey-level noise; lab_renderer_*: "
                    "the simulated lab's LabRenderer (config/lab.json, motion blur, sensor noise)";
  const PanelModel panel{make_procedural_panel(cv::Size(320, 240), 11), 0.40, 0.30};
  const PanelModel platform{make_procedural_panel(cv::Size(256, 256), 12), 0.60, 0.60};
  result.h264_seeds = h264_seeds;
  std::vector<Sequence> sequences = make_sequences(config, panel, platform, only, h264_kbps, h264_seeds);
  for (planar::TrackerKind kind : trackers) {
    const std::string tracker = to_string(kind);
    std::vector<ErrorSample> pooled, h264_pooled;
    for (const auto& s : sequences) {
      std::vector<ErrorSample> samples;
      SequenceStats& st = result.sequences.emplace_back(run_one(s, s.panel, kind, config, vision, samples, result.frames));
      st.range_bins = all_bins(tracker, samples);
      if (s.pooled) pooled.insert(pooled.end(), samples.begin(), samples.end());
      if (s.h264_seed) h264_pooled.insert(h264_pooled.end(), samples.begin(), samples.end());
    }
    for (const RangeBinStats& b : all_bins(tracker, pooled)) result.range_bins.push_back(b);
    for (const RangeBinStats& b : all_bins(tracker, h264_pooled)) result.h264_seed_bins.push_back(b);
  }
  return result;
}

}  // namespace labo::bench
