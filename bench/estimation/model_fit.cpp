#include "bench/estimation/model_fit.hpp"

#include <Eigen/Dense>
#include <cmath>
#include <random>
#include <stdexcept>
#include <string>

#include "core/frames.hpp"

namespace labo::bench {

namespace {
struct Sample {
  Seconds t = 0;  // measurement time
  NavdataSample nav;
  MoveCommand u;  // the command acting at t
};

// y = k1 * x1 + k2 * x2 by least squares over rows [begin, end).
Eigen::Vector2d fit2(const std::vector<Eigen::Vector3d>& rows, std::size_t begin, std::size_t end) {
  Eigen::Matrix2d A = Eigen::Matrix2d::Zero();
  Eigen::Vector2d b = Eigen::Vector2d::Zero();
  for (std::size_t i = begin; i < end; ++i) {
    const Eigen::Vector2d x(rows[i](1), rows[i](2));
    A += x * x.transpose();
    b += x * rows[i](0);
  }
  return A.ldlt().solve(b);
}

double residual(const std::vector<Eigen::Vector3d>& rows, std::size_t begin, std::size_t end, const Eigen::Vector2d& k) {
  double s = 0;
  for (std::size_t i = begin; i < end; ++i) {
    const double e = rows[i](0) - k(0) * rows[i](1) - k(1) * rows[i](2);
    s += e * e;
  }
  return end > begin ? std::sqrt(s / static_cast<double>(end - begin)) : 0.0;
}

// Rows (y, x1, x2) for first-order laws x' = a (b u - x) = (a b) u - a x.
struct Law {
  std::string name;
  std::vector<Eigen::Vector3d> rows;
};
}  // namespace

ModelFitReport fit_motion_model(EstimationPlant& plant, const estimation::MotionModelConstants& before, Seconds duration,
                                unsigned seed) {
  const Seconds navdata_delay = plant.navdata_delay(), control_delay = plant.command_latency();
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-0.6, 0.6), hold(0.4, 1.5);
  std::vector<std::pair<Seconds, MoveCommand>> sent;
  std::vector<NavdataSample> navdata;
  const Seconds t0 = plant.now();
  const Eigen::Vector3d start = plant.truth().T_world_body.translation();
  constexpr Seconds kFeedbackPeriod = 0.1;
  Seconds next_change = t0, next_feedback = t0;
  MoveCommand random;
  while (plant.now() < t0 + duration) {
    if (plant.now() >= next_change) {  // the excitation: random steps on every axis
      random = MoveCommand{u(rng), u(rng), u(rng), u(rng)};
      next_change = plant.now() + hold(rng);
      next_feedback = plant.now();
    }
    if (plant.now() >= next_feedback) {
      // Keep the flight inside a small volume around the start (a lab has walls and benches): a PD on
      // the true position, added to the random part (the fit itself sees only commands and navdata).
      const GroundTruth g = plant.truth();
      const Eigen::Vector3d p = g.T_world_body.translation() - start;
      const double yaw = ypr_from_rotation(g.T_world_body.linear())(0);
      const Eigen::Vector2d back = -0.2 * p.head<2>() - 0.3 * g.velocity_world.head<2>();
      MoveCommand c = random;
      c.gaz = std::clamp(random.gaz - 0.8 * p.z(), -1.0, 1.0);
      c.pitch = std::clamp(random.pitch + back.dot(Eigen::Vector2d(std::cos(yaw), std::sin(yaw))), -1.0, 1.0);
      c.roll = std::clamp(random.roll - back.dot(Eigen::Vector2d(-std::sin(yaw), std::cos(yaw))), -1.0, 1.0);
      plant.move(c);
      sent.emplace_back(plant.now(), c);
      next_feedback = plant.now() + kFeedbackPeriod;
    }
    plant.step(0.01, navdata);
    if (const std::string crash = plant.crash(); !crash.empty()) {
      const Eigen::Vector3d p = plant.truth().T_world_body.translation();
      throw std::runtime_error("fit_motion_model: the excitation flight crashed (" + crash + ") at t = " +
                               std::to_string(plant.now()) + " s, at (" + std::to_string(p.x()) + ", " +
                               std::to_string(p.y()) + ", " + std::to_string(p.z()) + ")");
    }
  }
  // Align: navdata at its measurement time, with the command acting then.
  std::vector<Sample> samples;
  std::size_t ci = 0;
  for (const NavdataSample& n : navdata) {
    const Seconds tm = n.t - navdata_delay;
    while (ci + 1 < sent.size() && sent[ci + 1].first + control_delay <= tm) ++ci;
    if (sent.empty() || sent[ci].first + control_delay > tm) continue;
    samples.push_back({tm, n, sent[ci].second});
  }
  Law attitude{"attitude", {}}, yaw{"yaw_rate", {}}, vertical{"vertical_speed", {}}, horizontal{"horizontal", {}};
  constexpr int k = 5;  // central differences over +-k samples
  // The yaw rate from yaw differences over +-k samples (a wider span: it is differentiated twice).
  const auto yaw_rate_at = [&](std::size_t i) {
    return wrap_angle(samples[i + k].nav.yaw_rad - samples[i - k].nav.yaw_rad) / (samples[i + k].t - samples[i - k].t);
  };
  for (std::size_t i = 2 * k + 1; i + 2 * k + 1 < samples.size(); ++i) {
    const Sample& s = samples[i];
    const Sample& a = samples[i - k];
    const Sample& b = samples[i + k];
    const double dt = b.t - a.t;
    if (dt <= 0 || dt > 0.2) continue;
    attitude.rows.emplace_back((b.nav.roll_rad - a.nav.roll_rad) / dt, s.u.roll, s.nav.roll_rad);
    attitude.rows.emplace_back((b.nav.pitch_rad - a.nav.pitch_rad) / dt, s.u.pitch, s.nav.pitch_rad);
    const double r = yaw_rate_at(i);
    yaw.rows.emplace_back((yaw_rate_at(i + k) - yaw_rate_at(i - k)) / dt, s.u.yaw_rate, r);
    vertical.rows.emplace_back((b.nav.vz_mps - a.nav.vz_mps) / dt, s.u.gaz, s.nav.vz_mps);
    // Body-level frame: dv/dt = a_body - omega x v, so a_body = dv/dt + r * (-vy, vx).
    const double ax = (b.nav.vx_mps - a.nav.vx_mps) / dt - r * s.nav.vy_mps;
    const double ay = (b.nav.vy_mps - a.nav.vy_mps) / dt + r * s.nav.vx_mps;
    const double fx = std::cos(s.nav.roll_rad) * std::sin(s.nav.pitch_rad), fy = -std::sin(s.nav.roll_rad);
    horizontal.rows.emplace_back(ax, fx, s.nav.vx_mps);
    horizontal.rows.emplace_back(ay, fy, s.nav.vy_mps);
  }
  ModelFitReport report;
  report.before = before;
  report.fitted = before;
  report.flight_s = duration;
  const auto first_order = [&](Law& law, double rate_before, double max_before, double& rate, double& max) {
    const std::size_t half = law.rows.size() / 2;
    const Eigen::Vector2d kf = fit2(law.rows, 0, half);
    rate = -kf(1);
    max = kf(0) / rate;
    report.laws.push_back({law.name, residual(law.rows, half, law.rows.size(), {rate_before * max_before, -rate_before}),
                           residual(law.rows, half, law.rows.size(), kf), static_cast<int>(law.rows.size())});
  };
  first_order(attitude, before.attitude_rate_hz, before.tilt_max_rad, report.fitted.attitude_rate_hz,
              report.fitted.tilt_max_rad);
  first_order(yaw, before.yaw_response_hz, before.yaw_rate_max_radps, report.fitted.yaw_response_hz,
              report.fitted.yaw_rate_max_radps);
  first_order(vertical, before.vertical_response_hz, before.vz_max_mps, report.fitted.vertical_response_hz,
              report.fitted.vz_max_mps);
  {
    const std::size_t half = horizontal.rows.size() / 2;
    const Eigen::Vector2d kf = fit2(horizontal.rows, 0, half);
    report.fitted.thrust_accel_mps2 = kf(0);
    report.fitted.drag_per_s = -kf(1);
    report.laws.push_back({horizontal.name,
                           residual(horizontal.rows, half, horizontal.rows.size(),
                                    {before.thrust_accel_mps2, -before.drag_per_s}),
                           residual(horizontal.rows, half, horizontal.rows.size(), kf),
                           static_cast<int>(horizontal.rows.size())});
  }
  return report;
}

}  // namespace labo::bench
