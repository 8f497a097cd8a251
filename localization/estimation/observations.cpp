#include "localization/estimation/observations.hpp"

namespace labo::estimation {

std::string_view to_string(LocalizationSource source) {
  switch (source) {
    case LocalizationSource::Slam: return "slam";
    case LocalizationSource::Homography: return "homography";
    case LocalizationSource::Face: return "face";
    case LocalizationSource::DeadReckoning: return "dead_reckoning";
  }
  return "?";
}

std::string_view to_string(SourceColour colour) {
  switch (colour) {
    case SourceColour::Green: return "green";
    case SourceColour::Blue: return "blue";
    case SourceColour::Red: return "red";
    case SourceColour::Black: return "black";
  }
  return "?";
}

}  // namespace labo::estimation
