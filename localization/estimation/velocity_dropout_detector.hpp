#pragma once
// VelocityDropoutDetector: tells when the navdata's bottom-camera velocity has failed, so the filter
// stops fusing it. Over a floor without texture the AR.Drone's optical flow finds nothing to follow
// and its velocity relaxes to zero while the drone keeps moving (drone/sim's SensorModel does the
// same); fused as "not moving", that zero stops the estimate behind the drone (docs/state-estimation.md,
// "Velocity dropout").
//
// The test is the motion model's: over the last `window_s`, a velocity at the window's start is
// propagated with the AR.Drone's horizontal dynamics (thrust along each packet's measured tilt, linear
// drag) and compared with the measured velocity now (averaged over `average_s`). A failing flow can
// only lose speed, towards zero:
//   - onset (while valid), from the filter's velocity at the window's start: the measured speed is
//     below the model's by more than `onset_mps`, and below `onset_ratio` of it, on `confirm_packets`
//     packets in a row: the flow lost speed the tilt does not explain (a drone that brakes tilts
//     back; one that coasts slows by the drag only);
//   - resume (while in dropout), on `confirm_packets` packets in a row: either the measured speed is
//     above `alive_mps` and not losing speed against the model propagated from the measured velocity
//     at the window's start (the flow follows the motion again), or it agrees within `agree_mps` with
//     the filter's model-propagated velocity (the drone stopped and the model knows it).
// At the onset the window's measurements were already fused: correction() gives the velocity and the
// displacement the model would have added over the window instead, for the filter to take back.
//
// Deterministic, timestamps only, a fixed-size ring buffer: no allocation per packet.
#include <Eigen/Core>
#include <array>
#include <cstddef>

#include "core/time.hpp"
#include "localization/estimation/estimation_config.hpp"

namespace labo {

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
  explicit VelocityDropoutDetector(const VelocityDropoutSettings& settings = {},
                                   const MotionModelConstants& model = {})
      : settings_(settings), model_(model) {}

  void reset();

  // One navdata packet at measurement time t: the measured horizontal velocity and the thrust
  // acceleration the measured tilt implies (both world frame), and the filter's horizontal velocity
  // before this packet's velocity update (model-propagated while in dropout).
  VelocityVerdict process(Seconds t, const Eigen::Vector2d& measured_world, const Eigen::Vector2d& thrust_accel_world,
                          const Eigen::Vector2d& filter_velocity);
  // The filter's horizontal velocity after this packet (recorded for the onset's take-back).
  void record_filter_velocity(const Eigen::Vector2d& filter_velocity);

  const DropoutCorrection& correction() const { return correction_; }
  bool in_dropout() const { return in_dropout_; }
  Seconds dropout_start() const { return dropout_start_; }
  const VelocityDropoutSettings& settings() const { return settings_; }

 private:
  struct Entry {
    Seconds t = 0;
    Eigen::Vector2d measured = Eigen::Vector2d::Zero();
    Eigen::Vector2d thrust_accel = Eigen::Vector2d::Zero();
    Eigen::Vector2d filter = Eigen::Vector2d::Zero();  // the filter's velocity after the packet
  };
  static constexpr std::size_t kCapacity = 160;  // 0.4 s of 200 Hz navdata, twice over

  const Entry& at(std::size_t i) const { return ring_[(head_ + i) % kCapacity]; }  // 0: oldest
  std::size_t first_at_or_after(Seconds t) const;
  Eigen::Vector2d mean_measured(std::size_t from, std::size_t to) const;  // entries [from, to]
  // The measured speed now and the model's, propagated over the window from its start: from the
  // filter's velocity there (the onset test: right after a resume the measurements at the window's
  // start may still be the failed flow's), or from the measured one (the resume test: a flow that
  // follows the motion again agrees with its own past, whatever the filter says).
  enum class Start { Filter, Measured };
  struct Consistency {
    bool valid = false;  // false without half a window of history
    double measured_speed = 0;
    double model_speed = 0;
  };
  Consistency consistency(Start from);
  void take_back(std::size_t start);

  VelocityDropoutSettings settings_;
  MotionModelConstants model_;
  std::array<Entry, kCapacity> ring_{};
  std::size_t head_ = 0;
  std::size_t size_ = 0;
  bool in_dropout_ = false;
  Seconds dropout_start_ = 0;
  int onset_votes_ = 0;
  int resume_votes_ = 0;
  DropoutCorrection correction_;
  std::array<Eigen::Vector2d, kCapacity> model_velocity_{};  // scratch: the model over the window
};

}  // namespace labo
