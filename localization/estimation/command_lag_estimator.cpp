#include "localization/estimation/command_lag_estimator.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace labo::estimation {

namespace {
constexpr std::size_t kCommandCapacity = 2048;   // 30-100 Hz over window + max lag
constexpr std::size_t kNavdataCapacity = 4096;   // 200 Hz full navdata over the window and more
constexpr Seconds kStartSpacing = 0.05;          // prediction starts at most every 50 ms
// A window with take-off, landing or a landed drone says nothing about the lag: the firmware follows
// PCMD only while flying or hovering.

double stddev(const std::vector<double>& v, std::size_t from, std::size_t to) {
  if (to <= from + 1) return 0;
  double sum = 0, sum2 = 0;
  for (std::size_t i = from; i < to; ++i) {
    sum += v[i];
    sum2 += v[i] * v[i];
  }
  const double n = static_cast<double>(to - from);
  const double mean = sum / n;
  return std::sqrt(std::max(0.0, sum2 / n - mean * mean));
}
}  // namespace

CommandLagEstimator::CommandLagEstimator(const MotionModelConstants& model, const CommandLagSettings& settings)
    : model_(model), settings_(settings), commands_(kCommandCapacity), navdata_(kNavdataCapacity) {
  const auto positive = [](double v) { return std::isfinite(v) && v > 0; };
  if (!positive(model.attitude_rate_hz) || !positive(model.tilt_max_rad))
    throw std::invalid_argument("CommandLagEstimator: attitude_rate_hz and tilt_max_rad must be positive");
  if (!positive(settings.window_s) || !positive(settings.evaluate_every_s) || !positive(settings.max_lag_s) ||
      !positive(settings.grid_s) || !positive(settings.horizon_s) || settings.median_of == 0 ||
      settings.grid_s * 4 > settings.max_lag_s || settings.horizon_s >= settings.window_s)
    throw std::invalid_argument(
        "CommandLagEstimator: settings must be positive, with grid_s <= max_lag_s / 4 and horizon_s < window_s");
  alpha_ = std::exp(-model.attitude_rate_hz * settings.grid_s);
  const auto grid_steps = static_cast<std::size_t>(std::ceil((settings.window_s + settings.max_lag_s) / settings.grid_s)) + 2;
  u_roll_.resize(grid_steps);
  u_pitch_.resize(grid_steps);
  errors_.resize(static_cast<std::size_t>(std::floor(settings.max_lag_s / settings.grid_s)) + 1);
  accepted_.resize(settings.median_of);
  sorted_.resize(settings.median_of);
}

void CommandLagEstimator::add_command(const MoveCommand& command, Seconds t_sent) {
  if (!std::isfinite(t_sent) || !std::isfinite(command.roll) || !std::isfinite(command.pitch)) {
    ++counters_.rejected_nonfinite;
    return;
  }
  if (t_sent < last_command_t_) {
    ++counters_.rejected_out_of_order;
    return;
  }
  last_command_t_ = t_sent;
  ++counters_.commands;
  // The driver clips to [-1, 1] before the wire; so does the model.
  if (commands_.full()) commands_.pop();
  commands_.push(t_sent, Tilt{std::clamp(command.roll, -1.0, 1.0) * model_.tilt_max_rad,
                              std::clamp(command.pitch, -1.0, 1.0) * model_.tilt_max_rad});
}

void CommandLagEstimator::add_navdata(const NavdataSample& sample) {
  if (!std::isfinite(sample.t) || !std::isfinite(sample.roll_rad) || !std::isfinite(sample.pitch_rad)) {
    ++counters_.rejected_nonfinite;
    return;
  }
  if (sample.t <= last_navdata_t_) {
    ++counters_.rejected_out_of_order;
    return;
  }
  if (navdata_.empty() && next_evaluation_t_ < sample.t)
    next_evaluation_t_ = sample.t + settings_.window_s + settings_.max_lag_s;
  last_navdata_t_ = sample.t;
  ++counters_.navdata;
  // A sample taken while the firmware ignores PCMD is stored as NaN: windows holding one are skipped.
  const double nan = std::nan("");
  const bool ok = control_state::follows_commands(sample.control_state);
  if (navdata_.full()) navdata_.pop();
  navdata_.push(sample.t, Tilt{ok ? sample.roll_rad : nan, ok ? sample.pitch_rad : nan});
  if (sample.t >= next_evaluation_t_) {
    evaluate(sample.t);
    next_evaluation_t_ = sample.t + settings_.evaluate_every_s;
  }
}

bool CommandLagEstimator::command_grid(Seconds g0, std::size_t n) {
  if (commands_.empty() || commands_.front().t > g0) return false;
  std::size_t k = 0;  // index (from the oldest) of the command in force
  for (std::size_t i = 0; i < n; ++i) {
    const Seconds t = g0 + static_cast<double>(i) * settings_.grid_s;
    while (k + 1 < commands_.size() && commands_.at(k + 1).t <= t) ++k;
    u_roll_[i] = commands_.at(k).item.roll;
    u_pitch_[i] = commands_.at(k).item.pitch;
  }
  return true;
}

double CommandLagEstimator::prediction_error(std::size_t lag_steps, bool pitch_axis, Seconds t0) const {
  const std::vector<double>& u = pitch_axis ? u_pitch_ : u_roll_;
  const Seconds g0 = t0 - settings_.max_lag_s;
  const auto grid_index = [&](Seconds t) { return static_cast<std::size_t>(std::lround((t - g0) / settings_.grid_s)); };
  const auto horizon_steps = static_cast<std::size_t>(std::lround(settings_.horizon_s / settings_.grid_s));
  const std::size_t last_grid = u.size() - 1;
  double sum2 = 0;
  std::size_t count = 0;
  Seconds last_start = -1e300;
  for (std::size_t s = 0; s < navdata_.size(); ++s) {
    const auto& start = navdata_.at(s);
    if (start.t < t0 || start.t < last_start + kStartSpacing) continue;
    last_start = start.t;
    double y = pitch_axis ? start.item.pitch : start.item.roll;
    std::size_t j = grid_index(start.t);
    const std::size_t j_end = std::min(j + horizon_steps, last_grid);
    for (std::size_t k = s + 1; k < navdata_.size(); ++k) {
      const auto& m = navdata_.at(k);
      const std::size_t jm = grid_index(m.t);
      if (jm > j_end) break;
      for (; j < jm; ++j) y = alpha_ * y + (1.0 - alpha_) * u[j - lag_steps];  // j >= max lag >= lag_steps
      const double e = (pitch_axis ? m.item.pitch : m.item.roll) - y;
      sum2 += e * e;
      ++count;
    }
  }
  return count > 0 ? sum2 / static_cast<double>(count) : 0.0;
}

void CommandLagEstimator::evaluate(Seconds t_end) {
  ++counters_.windows_evaluated;
  const Seconds t0 = t_end - settings_.window_s;
  const Seconds g0 = t0 - settings_.max_lag_s;
  // Any sample in the window taken while the firmware ignored the commands voids it.
  for (std::size_t s = 0; s < navdata_.size(); ++s) {
    const auto& a = navdata_.at(s);
    if (a.t >= t0 && std::isnan(a.item.roll)) {
      ++counters_.windows_low_excitation;
      return;
    }
  }
  if (navdata_.empty() || navdata_.front().t > t0 || !command_grid(g0, u_roll_.size())) {
    ++counters_.windows_low_excitation;
    return;
  }
  const auto first = static_cast<std::size_t>(std::lround(settings_.max_lag_s / settings_.grid_s));
  const bool use_roll = stddev(u_roll_, first, u_roll_.size()) >= settings_.min_command_std_rad;
  const bool use_pitch = stddev(u_pitch_, first, u_pitch_.size()) >= settings_.min_command_std_rad;
  if (!use_roll && !use_pitch) {
    ++counters_.windows_low_excitation;
    return;
  }
  for (std::size_t lag = 0; lag < errors_.size(); ++lag)
    errors_[lag] = (use_roll ? prediction_error(lag, false, t0) : 0.0) + (use_pitch ? prediction_error(lag, true, t0) : 0.0);
  const auto best_it = std::min_element(errors_.begin(), errors_.end());
  const auto best = static_cast<std::size_t>(best_it - errors_.begin());
  double mean = 0;
  for (double e : errors_) mean += e;
  mean /= static_cast<double>(errors_.size());
  const double contrast = mean > 0 ? 1.0 - *best_it / mean : 0.0;
  if (best == 0 || best + 1 >= errors_.size() || contrast < settings_.min_contrast) {
    ++counters_.windows_unclear;
    return;
  }
  // Parabola through the best candidate and its neighbours.
  const double a = errors_[best - 1], b = errors_[best], c = errors_[best + 1];
  const double curvature = a - 2 * b + c;
  const double offset = curvature > 0 ? std::clamp(0.5 * (a - c) / curvature, -0.5, 0.5) : 0.0;
  const Seconds lag_s = (static_cast<double>(best) + offset) * settings_.grid_s;
  // The newest median_of windows (order does not matter for their median).
  accepted_[counters_.windows_accepted % accepted_.size()] = lag_s;
  ++counters_.windows_accepted;
  const auto n = static_cast<std::ptrdiff_t>(std::min<std::uint64_t>(counters_.windows_accepted, accepted_.size()));
  std::copy(accepted_.begin(), accepted_.begin() + n, sorted_.begin());
  const auto mid = sorted_.begin() + n / 2;
  std::nth_element(sorted_.begin(), mid, sorted_.begin() + n);
  current_ = CommandLagEstimate{*mid, static_cast<std::size_t>(n), contrast};
}

}  // namespace labo::estimation
