#include "bench/experiments/flight_plot.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <numbers>
#include <sstream>
#include <stdexcept>

namespace labo::bench {

namespace {

std::ofstream open_for_writing(const std::filesystem::path& file) {
  std::ofstream out(file);
  if (!out) throw std::runtime_error("cannot write " + file.string());
  return out;
}

// Its N columns, empty when there is no value.
template <int N>
void write_optional(std::ostream& out, const std::optional<Eigen::Matrix<double, N, 1>>& v) {
  for (int i = 0; i < N; ++i) {
    out << ',';
    if (v) out << (*v)[i];
  }
}

constexpr const char* kAxisNames[] = {"x (m)", "y (m)", "z (m)", "yaw (deg)"};

double value(const Eigen::Vector4d& v, int axis) {
  return axis == 3 ? v[3] * 180.0 / std::numbers::pi : v[axis];
}

}  // namespace

void write_flight_csv(const std::filesystem::path& file, const std::vector<FlightSample>& samples) {
  std::ofstream out = open_for_writing(file);
  out << "t_s,est_x_m,est_y_m,est_z_m,est_yaw_rad,true_x_m,true_y_m,true_z_m,true_yaw_rad,"
         "des_x_m,des_y_m,des_z_m,des_yaw_rad,source,slam,target,target_lost_reason,target_method,stage_index,stage,"
         "face_x_m,face_y_m,face_z_m,face_heading_rad,face_cam_x_m,face_cam_y_m,face_cam_z_m,"
         "face_meas_cam_x_m,face_meas_cam_y_m,face_meas_cam_z_m,cmd_roll,cmd_pitch,cmd_gaz,cmd_yaw_rate,action,alerts,"
         "object_fused,slam_fused,rejected_reacquisition,reacquisition_confirmed,rejected_innovation,rejected_jump,"
         "velocity_dropouts,velocity_dropout_packets,est_vx_mps,est_vy_mps,est_sigma_m,est_drift_bound_m\n";
  for (const auto& s : samples) {
    out << s.t;
    for (int i = 0; i < 4; ++i) out << ',' << s.estimated[i];
    for (int i = 0; i < 4; ++i) out << ',' << s.truth[i];
    for (int i = 0; i < 4; ++i) {
      out << ',';
      if (s.desired) out << (*s.desired)[i];
    }
    std::string stage = s.stage, reason = s.target_reason;
    std::replace(stage.begin(), stage.end(), ',', ';');
    std::replace(reason.begin(), reason.end(), ',', ';');
    out << ',' << to_string(s.source) << ',' << to_string(s.slam) << ',' << to_string(s.target) << ",\"" << reason << "\"," << s.target_method << ','
        << s.stage_index << ",\"" << stage << '"';
    write_optional(out, s.face_true_world);
    write_optional(out, s.face_true_cam);
    write_optional(out, s.face_measured_cam);
    for (int i = 0; i < 4; ++i) out << ',' << s.command[i];
    std::string alerts = s.alerts;
    std::replace(alerts.begin(), alerts.end(), ',', ';');
    const EstimatorCounts& e = s.estimator;
    out << ',' << s.action << ",\"" << alerts << "\"," << e.object_fused << ',' << e.slam_fused << ','
        << e.rejected_reacquisition << ',' << e.reacquisition_confirmed << ',' << e.rejected_innovation << ','
        << e.rejected_jump << ',' << e.velocity_dropouts << ',' << e.velocity_dropout_packets << ','
        << s.estimated_velocity.x() << ',' << s.estimated_velocity.y() << ',' << s.position_sigma_m << ',' << s.drift_bound_m << '\n';
  }
}

void write_flight_svg(const std::filesystem::path& file, const std::vector<FlightSample>& samples, const std::string& title) {
  std::ofstream out = open_for_writing(file);
  const double W = 900, panel_h = 170, left = 60, right = 20, top = 40;
  const double H = top + 4 * (panel_h + 25) + 30;
  out << "<svg xmlns='http://www.w3.org/2000/svg' width='" << W << "' height='" << H << "' font-family='sans-serif' font-size='11'>\n"
      << "<rect width='100%' height='100%' fill='white'/>\n<text x='" << left << "' y='20' font-size='14'>" << title << "</text>\n"
      << "<text x='" << W - 420 << "' y='20'>estimate: <tspan fill='" << fusion::colour_of(fusion::FeedbackSource::Slam) << "'>SLAM</tspan> "
      << "<tspan fill='" << fusion::colour_of(fusion::FeedbackSource::Homography) << "'>homography</tspan> "
      << "<tspan fill='" << fusion::colour_of(fusion::FeedbackSource::Face) << "'>face</tspan> "
      << "<tspan fill='" << fusion::colour_of(fusion::FeedbackSource::DeadReckoning) << "'>dead reckoning</tspan>; "
      << "<tspan fill='#888'>true</tspan>, <tspan fill='#00bcd4'>desired</tspan></text>\n";
  if (samples.empty()) return;
  const double t0 = samples.front().t, t1 = std::max(samples.back().t, t0 + 1e-3);
  for (int axis = 0; axis < 4; ++axis) {
    double lo = 1e9, hi = -1e9;
    for (const auto& s : samples) {
      for (double v : {value(s.estimated, axis), value(s.truth, axis)}) lo = std::min(lo, v), hi = std::max(hi, v);
      if (s.desired) lo = std::min(lo, value(*s.desired, axis)), hi = std::max(hi, value(*s.desired, axis));
    }
    if (hi - lo < 1e-3) hi = lo + 1;
    const double y0 = top + axis * (panel_h + 25);
    auto X = [&](double t) { return left + (t - t0) / (t1 - t0) * (W - left - right); };
    auto Y = [&](double v) { return y0 + panel_h - (v - lo) / (hi - lo) * panel_h; };
    out << "<rect x='" << left << "' y='" << y0 << "' width='" << W - left - right << "' height='" << panel_h
        << "' fill='none' stroke='#ccc'/>\n<text x='4' y='" << y0 + 12 << "'>" << kAxisNames[axis] << "</text>\n"
        << "<text x='4' y='" << y0 + panel_h << "'>" << lo << "</text><text x='4' y='" << y0 + 24 << "'>" << hi << "</text>\n";
    auto polyline = [&](auto get, const std::string& colour, const std::string& extra) {
      std::ostringstream pts;
      for (const auto& s : samples)
        if (auto v = get(s)) pts << X(s.t) << ',' << Y(*v) << ' ';
      out << "<polyline fill='none' stroke='" << colour << "' " << extra << " points='" << pts.str() << "'/>\n";
    };
    polyline([&](const FlightSample& s) { return std::optional<double>(value(s.truth, axis)); }, "#888", "stroke-dasharray='4 3'");
    polyline([&](const FlightSample& s) { return s.desired ? std::optional<double>(value(*s.desired, axis)) : std::nullopt; },
             "#00bcd4", "stroke-width='1.5'");
    // The estimate, one segment per run of the same source.
    std::size_t i = 0;
    while (i < samples.size()) {
      std::size_t j = i;
      std::ostringstream pts;
      while (j < samples.size() && samples[j].source == samples[i].source) {
        pts << X(samples[j].t) << ',' << Y(value(samples[j].estimated, axis)) << ' ';
        ++j;
      }
      if (j < samples.size()) pts << X(samples[j].t) << ',' << Y(value(samples[j].estimated, axis));
      out << "<polyline fill='none' stroke='" << fusion::colour_of(samples[i].source) << "' stroke-width='1.5' points='" << pts.str() << "'/>\n";
      i = j;
    }
  }
  out << "<text x='" << W / 2 << "' y='" << H - 8 << "'>t (s)</text>\n</svg>\n";
}

}  // namespace labo::bench
