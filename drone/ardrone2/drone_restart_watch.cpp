#include "drone/ardrone2/drone_restart_watch.hpp"

#include "drone/ardrone2/navdata_schema.hpp"

namespace labo::ardrone2 {

bool DroneRestartWatch::in_configured_mode(const NavdataPacket& packet) const {
  if (packet.state_bit(kStateBootstrap)) return false;
  return !demo_expected_ || packet.has(kTagDemo);
}

bool DroneRestartWatch::restarted(const NavdataPacket& packet, bool sequence_restarted) {
  const bool configured_now = in_configured_mode(packet);
  if (sequence_restarted || (configured_ && !configured_now)) {
    configured_ = false;
    return true;
  }
  if (configured_now) configured_ = true;
  return false;
}

}  // namespace labo::ardrone2
