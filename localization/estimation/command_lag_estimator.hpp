#pragma once
// CommandLagEstimator: measures, from flight data alone, the round trip from a command leaving
// LaboDrone to its effect showing in the navdata: control delay + navdata delay. The AR.Drone has no
// echo to ping and its video and navdata stamps are on clocks that are not synchronised with each
// other nor with ours, so this lag is the one delay that can be measured on the link; the estimator's
// control delay is this round trip minus the navdata delay (../../docs/state-estimation.md).
//
// Method: the firmware tilts the drone towards the commanded angle as a first-order lag
// (MotionModelConstants: attitude_rate_hz, tilt_max_rad). For each candidate lag d on a grid, the
// measured roll and pitch are predicted a short horizon ahead from each measured sample, driven by
// the commands shifted by d; the lag with the least prediction error wins, refined by a parabola
// through its neighbours. Short horizons keep what the model leaves out (the firmware's own hover
// braking, a tilt offset) from dominating. A window counts only if the commands moved enough and the
// error curve has a clear minimum inside the searched range; the reported figure is the median of
// the last accepted windows.
//
// Inputs carry their own timestamps (receive time for navdata, send time for commands); no wall
// clock, no allocation after construction. Non-finite values and times running backwards are
// refused and counted.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "core/time.hpp"
#include "drone/drone_link.hpp"
#include "localization/estimation/estimation_config.hpp"
#include "localization/estimation/timed_queue.hpp"

namespace labo::estimation {

struct CommandLagSettings {
  Seconds window_s = 6.0;            // flight data per evaluation
  Seconds evaluate_every_s = 2.0;    // a new window every this much navdata time
  Seconds max_lag_s = 0.40;          // candidates 0 .. max_lag_s
  Seconds grid_s = 0.005;            // candidate spacing and simulation step
  Seconds horizon_s = 0.30;          // prediction horizon from each measured sample
  double min_command_std_rad = 0.02; // commanded tilt must move at least this much (about 1.1 deg)
  double min_contrast = 0.15;        // 1 - best error / mean error over the candidates
  std::size_t median_of = 9;         // accepted windows in the reported median
};

struct CommandLagEstimate {
  Seconds round_trip_s = 0;          // median of the accepted windows
  std::size_t windows = 0;           // accepted windows behind it
  double contrast = 0;               // of the newest accepted window
};

struct CommandLagCounters {
  std::uint64_t navdata = 0, commands = 0;
  std::uint64_t rejected_nonfinite = 0, rejected_out_of_order = 0;
  std::uint64_t windows_evaluated = 0, windows_low_excitation = 0, windows_unclear = 0, windows_accepted = 0;
};

class CommandLagEstimator {
 public:
  explicit CommandLagEstimator(const MotionModelConstants& model, const CommandLagSettings& settings = {});

  // A command as sent at t_sent (roll/pitch are fractions of tilt_max, as in MoveCommand).
  void add_command(const MoveCommand& command, Seconds t_sent);
  // Navdata at its receive time; may evaluate a window (a few ms of CPU every evaluate_every_s).
  void add_navdata(const NavdataSample& sample);

  std::optional<CommandLagEstimate> estimate() const { return current_; }
  const CommandLagCounters& counters() const { return counters_; }

 private:
  struct Tilt { double roll = 0, pitch = 0; };  // rad

  void evaluate(Seconds t_end);
  // Fills u_ on the grid from t0 for n steps (zero-order hold of the commands sent); false if the
  // commands do not reach back to t0.
  bool command_grid(Seconds t0, std::size_t n);
  double prediction_error(std::size_t lag_steps, bool pitch_axis, Seconds t0) const;

  MotionModelConstants model_;
  CommandLagSettings settings_;
  double alpha_ = 0;                 // exp(-attitude_rate * grid): one grid step of the lag

  // Fixed-capacity rings (the oldest dropped when full): commanded and measured tilt.
  TimedQueue<Tilt> commands_;
  TimedQueue<Tilt> navdata_;

  // Scratch, sized once.
  std::vector<double> u_roll_, u_pitch_, errors_;
  std::vector<Seconds> accepted_;
  std::vector<Seconds> sorted_;
  std::optional<CommandLagEstimate> current_;

  Seconds last_command_t_ = -1e300, last_navdata_t_ = -1e300, next_evaluation_t_ = -1e300;
  CommandLagCounters counters_;
};

}  // namespace labo::estimation
