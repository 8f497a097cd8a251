#pragma once
// Chooses the visual source that corrects the filter, as in the paper's §3 and §6.2: SLAM when far
// from the target, the homography of the planar target when near, the face in face-follow, dead
// reckoning (navdata + prediction) when none is usable. Hysteresis in distance (homography below
// far_to_near_m, back to SLAM above near_to_far_m) and in time (a source must be good for
// source_hold_s before it is taken, and lost that long before it is dropped) keeps it from chattering.
// When SLAM is not usable, a target tracked at any distance is taken over dead reckoning, and kept
// beyond near_to_far_m until SLAM is good again. SLAM counts as usable only when Good and scaled
// (what LabPipelines fuses); a Dodgy SLAM does not correct the filter, so it is no source.
#include <optional>

#include "localization/fusion/localization_pipelines.hpp"

namespace labo::fusion {

// The switch's hysteresis (config "control.mission": far_to_near_m, near_to_far_m, source_hold_s).
struct SourceSwitchParameters {
  double far_to_near_m = 1.6;  // homography below this distance ...
  double near_to_far_m = 2.0;  // ... SLAM again above this one
  double source_hold_s = 0.5;  // a source must stay good (or lost) this long before it is taken (dropped)
};

struct SwitchInputs {
  Seconds t = 0;
  TrackState target_state = TrackState::Off;  // instrument (front) or platform (bottom)
  std::optional<double> target_distance_m;    // camera to target, when known
  SlamState slam = SlamState::Off;
  // SLAM poses are metric only once the estimator has fixed the map's scale; before that the
  // estimator does not fuse them, so SLAM is no source to choose (nor to fall back on).
  bool slam_scaled = true;
  bool face_mode = false;
  TrackState face_state = TrackState::Off;
};

class LocalizationSwitch {
 public:
  explicit LocalizationSwitch(const SourceSwitchParameters& params) : params_(params) {}
  FeedbackSource update(const SwitchInputs& in);
  FeedbackSource current() const { return current_; }
  void reset(FeedbackSource source = FeedbackSource::DeadReckoning);

 private:
  bool held(bool condition, Seconds& since, Seconds t) const;

  SourceSwitchParameters params_;
  FeedbackSource current_ = FeedbackSource::DeadReckoning;
  Seconds target_good_since_ = -1;
  Seconds target_seen_since_ = -1;
  Seconds target_bad_since_ = -1;
  Seconds slam_good_since_ = -1;
  Seconds slam_bad_since_ = -1;
  Seconds face_good_since_ = -1;
  Seconds face_bad_since_ = -1;
};

}  // namespace labo::fusion
