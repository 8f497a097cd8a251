#include "drone/drone_link.hpp"

namespace labo {

std::string to_string(LinkState state) {
  switch (state) {
    case LinkState::Disconnected: return "disconnected";
    case LinkState::Connecting: return "connecting";
    case LinkState::Connected: return "connected";
    case LinkState::Degraded: return "degraded";
    case LinkState::Lost: return "lost";
  }
  return "?";
}

}  // namespace labo
