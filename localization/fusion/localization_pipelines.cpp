#include "localization/fusion/localization_pipelines.hpp"

namespace labo::fusion {

std::string to_string(FeedbackSource source) {
  switch (source) {
    case FeedbackSource::Slam: return "slam";
    case FeedbackSource::Homography: return "homography";
    case FeedbackSource::Face: return "face";
    case FeedbackSource::DeadReckoning: return "dead_reckoning";
  }
  return "unknown";
}

// The paper's colour code: green SLAM, blue homography, red/black dead reckoning; face in purple.
std::string colour_of(FeedbackSource source) {
  switch (source) {
    case FeedbackSource::Slam: return "#1a9850";
    case FeedbackSource::Homography: return "#2166ac";
    case FeedbackSource::Face: return "#984ea3";
    case FeedbackSource::DeadReckoning: return "#d73027";
  }
  return "#000000";
}

std::string to_string(TrackState state) {
  switch (state) {
    case TrackState::Off: return "off";
    case TrackState::Searching: return "searching";
    case TrackState::Tracking: return "tracking";
    case TrackState::Lost: return "lost";
  }
  return "unknown";
}

std::string to_string(SlamState state) {
  switch (state) {
    case SlamState::Off: return "off";
    case SlamState::Initializing: return "initializing";
    case SlamState::Good: return "good";
    case SlamState::Dodgy: return "dodgy";
    case SlamState::Lost: return "lost";
  }
  return "unknown";
}

}  // namespace labo::fusion
