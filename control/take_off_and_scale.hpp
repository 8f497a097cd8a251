#pragma once
// Stage 1 of every mission that flies on a metric SLAM map (inspect, the paper's §6.2; find teacher):
// take off, climb to the mission's altitude, wait for SLAM to initialize (or time out and go on
// without it), fly scale_manoeuvre_m forward along the camera's axis and back, then the scale
// manoeuvre - the set point moving slowly up by scale_manoeuvre_m and back down, the vertical motion
// the estimator's ScaleEstimator compares with the ultrasound to fix the map's scale. Why the forward
// leg first: a map made from the take-off's vertical motion in front of a far wall confuses vertical
// translation with pitch, and its scale changes by 25-75 % at its first motion along the optical axis
// (docs/state-estimation.md, "Scale"); flown first, that change is over before the scale is fixed.
// When the map still has no scale after a round (too few good displacement pairs), the round is
// repeated, up to kMaxRounds in all: without a scale the whole mission would fly on dead reckoning and
// the homography and could miss the platform. Test "control: a map still without a scale flies the
// vertical manoeuvre again, kMaxRounds times in all".
#include <string>

#include "control/mission.hpp"

namespace labo::control {

class TakeOffAndScale {
 public:
  static constexpr int kMaxRounds = 3;

  // One control tick, climbing to altitude_m; true once stage 1 is over (scale fixed, or the
  // manoeuvre skipped or timed out).
  bool step(MissionContext& ctx, double altitude_m);
  bool done() const { return step_ == Step::Done; }
  // What the stage does and waits for, for the stage line: "climbing to 1.20 m", "initializing SLAM:
  // waiting for a map (2.0 s of 8 s)", "scale manoeuvre (up): waiting for scale: 1/3 pairs", ...
  std::string describe() const;

 private:
  enum class Step { TakeOff, Climb, SlamInit, Forward, Back, Up, Down, Done };
  void enter(Step step, Seconds t) {
    step_ = step;
    since_ = t;
    fresh_ = true;
  }

  Step step_ = Step::TakeOff;
  Seconds since_ = 0;
  bool fresh_ = true;
  double start_z_ = 0;
  PoseTarget leg_start_;  // where the forward leg started (and the back leg ends)
  int round_ = 0;
  // What describe() reports, as of the last step.
  double altitude_m_ = 0;
  Seconds last_t_ = 0;
  fusion::SlamSummary slam_;
};

}  // namespace labo::control
