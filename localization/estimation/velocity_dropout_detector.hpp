#pragma once
// VelocityDropoutDetector: tells when the navdata's bottom-camera velocity has failed, so the filter
// stops fusing it. Over a floor without texture the AR.Drone's optical flow finds nothing to follow
// and its velocity relaxes to zero while the drone keeps moving (drone/sim's SensorModel does the
// same); fused as "not moving", that zero stops the estimate behind the drone (docs/state-estimation.md,
// "Velocity dropout").
//
// The reference is the AR.Drone's horizontal motion model, thrust along the measured tilt against a
// linear drag, run independently of the filter:
//   - tilt bias: the IMU's roll/pitch carry an offset (0.6 deg without a flat trim) that the model
//     would take for a steady push of ~0.1 m/s^2. While the flow is valid it is learned from the
//     model's residual over each window (the mean thrust minus drag minus the measured velocity's
//     change), averaged over the first `kBiasWarmup` seconds of flight (the take-off, over the
//     platform's texture), then followed with a slow time constant while the flow shows motion and
//     agrees with the model.
//     The filter's model gets it too (DroneEkf::set_tilt_bias_accel).
//   - the model's velocity ("shadow"): propagated with the bias-corrected thrust and drag, pulled
//     gently towards the measured velocity while it is valid (so a model error does not accumulate),
//     left on its own during a dropout. A measured velocity that no failing flow could make of it
//     (faster, backwards or sideways by more than `onset_mps`) is a motion the model missed (a push,
//     a gust): the shadow takes the measured velocity.
//   - onset (valid, after the warm-up): the measured speed is below the shadow's by more than
//     `onset_mps` and below `onset_ratio` of it, on `confirm_packets` packets in a row. A failing
//     flow only loses speed, towards zero; a drone that brakes tilts back and one that coasts slows
//     by the drag, and the shadow knows both. The pull is slow (7 s), so a drone that creeps on a
//     small sustained tilt while the flow reads zero is caught too (from about 0.5 deg).
//   - resume (dropout), on `confirm_packets` packets in a row: either the measured speed is above
//     `alive_mps` and not losing speed against the model propagated over `window_s` from the measured
//     velocity at the window's start (the flow follows the motion again), or it agrees within
//     `agree_mps` with the filter's velocity (the drone stopped and the model knows it).
// At the onset the failing measurements were already fused: correction() gives the velocity and the
// displacement the shadow moved more than the filter since they last agreed (at least over the last
// `window_s`, at most over the ring), for the filter to take back.
//
// Deterministic, timestamps only, a fixed-size ring buffer: no allocation per packet.
#include <Eigen/Core>
#include <array>
#include <cstddef>

#include "core/time.hpp"
#include "localization/estimation/estimation_config.hpp"

namespace labo::estimation {

// What the filter is told per packet.
struct VelocityVerdict {
  bool fuse = true;     // fuse this packet's horizontal velocity
  bool onset = false;   // a dropout starts at this packet: apply correction()
  bool resumed = false; // fusing again after a dropout
};

// The take-back at an onset: add to the filter's horizontal velocity and position (world frame).
struct DropoutCorrection {
  Eigen::Vector2d velocity = Eigen::Vector2d::Zero();
  Eigen::Vector2d position = Eigen::Vector2d::Zero();
};

class VelocityDropoutDetector {
 public:
  // `firmware_command_hold_s`: a silence in the navdata longer than this starts the model again
  // (the drone's firmware hovered it meanwhile, which the model cannot know); shorter ones are flown
  // on the last command, as the model has it.
  explicit VelocityDropoutDetector(const VelocityDropoutSettings& settings = {},
                                   const MotionModelConstants& model = {}, Seconds firmware_command_hold_s = 2.0)
      : settings_(settings), model_(model), firmware_command_hold_s_(firmware_command_hold_s) {}

  // Forgets everything, the learned tilt bias too (a new filter, or landed: a flat trim may follow).
  void reset();

  // One navdata packet at measurement time t: the measured horizontal velocity and the thrust
  // acceleration the measured tilt implies (both world frame, the thrust without the tilt bias), the
  // filter's yaw, and the filter's horizontal velocity before this packet's velocity update.
  VelocityVerdict process(Seconds t, const Eigen::Vector2d& measured_world, const Eigen::Vector2d& thrust_accel_world,
                          double yaw, const Eigen::Vector2d& filter_velocity);
  // The filter's horizontal velocity after this packet (recorded for the onset's take-back).
  void record_filter_velocity(const Eigen::Vector2d& filter_velocity);

  const DropoutCorrection& correction() const { return correction_; }
  bool in_dropout() const { return in_dropout_; }
  Seconds dropout_start() const { return dropout_start_; }
  const VelocityDropoutSettings& settings() const { return settings_; }
  // The learned tilt bias as an acceleration in the heading frame (x forward, y left), m/s^2: what
  // the model's thrust along the measured tilt overstates.
  const Eigen::Vector2d& tilt_bias_accel() const { return bias_heading_; }
  bool warmed_up() const { return bias_time_ >= kBiasWarmup; }

  static constexpr Seconds kBiasWarmup = 3.0;         // valid flow before onsets are judged
  static constexpr Seconds kBiasTimeConstant = 10.0;  // afterwards
  static constexpr double kShadowPullPerS = 0.15;     // the shadow's pull towards a valid measurement
  static constexpr Seconds kTakeBackMaxS = 1.3;       // an onset takes back at most this span
  static constexpr double kBiasGateMps2 = 0.4;        // a window's residual above this (2.3 deg) is no offset

 private:
  struct Entry {
    Seconds t = 0;
    Eigen::Vector2d measured = Eigen::Vector2d::Zero();
    Eigen::Vector2d thrust_accel = Eigen::Vector2d::Zero();  // bias-corrected, world frame
    Eigen::Vector2d filter = Eigen::Vector2d::Zero();        // the filter's velocity after the packet
    Eigen::Vector2d shadow = Eigen::Vector2d::Zero();        // the model's velocity after the packet
  };
  static constexpr std::size_t kCapacity = 256;  // 1.3 s of 200 Hz navdata, 17 s of 15 Hz

  // Forgets the flight (the ring, the dropout, the model's velocity) but keeps the learned tilt bias.
  void restart();
  const Entry& at(std::size_t i) const { return ring_[(head_ + i) % kCapacity]; }  // 0: oldest
  Entry& back() { return ring_[(head_ + size_ - 1) % kCapacity]; }
  std::size_t first_at_or_after(Seconds t) const;
  Eigen::Vector2d mean_measured(std::size_t from, std::size_t to) const;  // entries [from, to]
  void push(const Entry& e);
  // The window [now - window_s, now], when at least half of it has history: its first entry, the
  // last entry of its start's averaging span, the first of its end's.
  struct Window {
    bool valid = false;
    std::size_t start = 0, start_end = 0, end_begin = 0;
  };
  Window window() const;
  // The model from the window's start (measured velocity there) to now: its mean over the end's span.
  Eigen::Vector2d model_from_measured(const Window& w) const;
  void learn_bias(const Window& w, double yaw, Seconds dt);
  // How far `measured` is from anything a failing flow could make of the shadow's velocity (m/s).
  double unexplained_by_failing_flow(const Eigen::Vector2d& measured) const;
  void take_back();

  VelocityDropoutSettings settings_;
  MotionModelConstants model_;
  Seconds firmware_command_hold_s_;
  std::array<Entry, kCapacity> ring_{};
  std::size_t head_ = 0;
  std::size_t size_ = 0;
  bool in_dropout_ = false;
  Seconds dropout_start_ = 0;
  int onset_votes_ = 0;
  int resume_votes_ = 0;
  Eigen::Vector2d shadow_ = Eigen::Vector2d::Zero();
  Eigen::Vector2d bias_heading_ = Eigen::Vector2d::Zero();
  Seconds consistent_since_ = 0;  // the last packet where the flow and the shadow agreed
  Seconds shadow_reset_t_ = 0;    // the last time the shadow took the measured velocity
  Seconds bias_time_ = 0;  // valid flow seen by the bias (saturates after the warm-up)
  DropoutCorrection correction_;
};

}  // namespace labo::estimation
