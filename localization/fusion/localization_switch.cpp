#include "localization/fusion/localization_switch.hpp"

namespace labo::fusion {

bool LocalizationSwitch::held(bool condition, Seconds& since, Seconds t) const {
  if (!condition) {
    since = -1;
    return false;
  }
  if (since < 0) since = t;
  return t - since >= params_.source_hold_s;
}

void LocalizationSwitch::reset(FeedbackSource source) {
  current_ = source;
  target_good_since_ = target_seen_since_ = target_bad_since_ = slam_good_since_ = slam_bad_since_ = -1;
  face_good_since_ = face_bad_since_ = -1;
}

FeedbackSource LocalizationSwitch::update(const SwitchInputs& in) {
  // Only what LabPipelines fuses counts: Good SLAM frames. Dodgy ones are not fused, so "SLAM" while
  // SLAM stays dodgy is dead reckoning in disguise: it would ignore a panel tracked in the hysteresis
  // band, and the safety monitor's dead-reckoning hover would land the drone. Test "control: a dodgy
  // SLAM (not fused) is no source: a tracked target is taken instead".
  const bool slam_ok = in.slam == SlamState::Good && in.slam_scaled;
  const bool slam_good = held(slam_ok, slam_good_since_, in.t);
  const bool slam_gone = held(!slam_ok, slam_bad_since_, in.t);
  const bool tracking = in.target_state == TrackState::Tracking;
  const bool near = in.target_distance_m && *in.target_distance_m < params_.far_to_near_m;
  const bool far = !in.target_distance_m || *in.target_distance_m > params_.near_to_far_m;
  const bool target_good = held(tracking && near, target_good_since_, in.t);
  // Tracked at any distance: better than dead reckoning when SLAM is not usable.
  const bool target_seen = held(tracking, target_seen_since_, in.t);
  const bool target_gone = held(!tracking, target_bad_since_, in.t);
  const bool face_good = held(in.face_state == TrackState::Tracking, face_good_since_, in.t);
  const bool face_gone = held(in.face_state != TrackState::Tracking, face_bad_since_, in.t);

  auto fallback = [&] { return slam_ok && (slam_good || current_ == FeedbackSource::Slam) ? FeedbackSource::Slam
                                                                                           : FeedbackSource::DeadReckoning; };
  switch (current_) {
    case FeedbackSource::Face:
      if (!in.face_mode || face_gone) current_ = fallback();
      break;
    case FeedbackSource::Homography:
      if (target_gone || (far && slam_good)) current_ = fallback();
      break;
    case FeedbackSource::Slam:
      if (slam_gone) current_ = FeedbackSource::DeadReckoning;
      break;
    case FeedbackSource::DeadReckoning:
      if (slam_good) current_ = FeedbackSource::Slam;
      break;
  }
  if (in.face_mode && face_good) current_ = FeedbackSource::Face;
  else if (!in.face_mode && (target_good || (target_seen && current_ == FeedbackSource::DeadReckoning)))
    current_ = FeedbackSource::Homography;
  return current_;
}

}  // namespace labo::fusion
