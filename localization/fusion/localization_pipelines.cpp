#include "localization/fusion/localization_pipelines.hpp"

#include "core/frames.hpp"

namespace labo::fusion {

Eigen::Vector3d offset_along_heading(const Eigen::Vector3d& in_body_m, double pitch_rad, double roll_rad) {
  return rotation_from_ypr(0.0, pitch_rad, roll_rad) * in_body_m;
}

std::string to_string(FeedbackSource source) {
  switch (source) {
    case FeedbackSource::Slam: return "slam";
    case FeedbackSource::Homography: return "homography";
    case FeedbackSource::Face: return "face";
    case FeedbackSource::DeadReckoning: return "dead_reckoning";
  }
  return "unknown";
}

// The paper's colour code: green while SLAM tracks, blue from the panel's homography, red on navdata
// alone; the face (not coloured in the paper) orange. The server's overlays and the page use these
// same values (server/lab/flight_service.cpp adds black for a lost object track).
std::string colour_of(FeedbackSource source) {
  switch (source) {
    case FeedbackSource::Slam: return "#00b000";
    case FeedbackSource::Homography: return "#1060ff";
    case FeedbackSource::Face: return "#ff9000";
    case FeedbackSource::DeadReckoning: return "#e00000";
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
