#pragma once
// Tells from the navdata alone that the drone restarted under a link that stayed up (a battery swap,
// a firmware reboot faster than link.lost_after_s): a restarted AR.Drone 2.0 streams in bootstrap
// mode again (state bit 11, header and checksum only, no demo option) and counts its navdata
// sequence from 1 again. The driver then has to redo the start-up configuration, or the drone stays
// in bootstrap mode and the flight software never sees its battery or control state again. No I/O.
#include "drone/ardrone2/navdata_packet.hpp"

namespace labo::ardrone2 {

class DroneRestartWatch {
 public:
  // `demo_expected`: the driver asks for navdata_demo TRUE, so a configured drone sends the demo option.
  explicit DroneRestartWatch(bool demo_expected) : demo_expected_(demo_expected) {}

  // One navdata packet, in order (`sequence_restarted`: the sequence filter saw the count start
  // again). True once per restart: when a drone that had been configured is back in bootstrap mode
  // (or without the demo option it was configured for), or its sequence started again.
  bool restarted(const NavdataPacket& packet, bool sequence_restarted);
  // The start-up configuration was queued for another reason (a reconnection after a loss): wait for
  // it to take effect before watching again.
  void configuring() { configured_ = false; }
  bool configured() const { return configured_; }

 private:
  bool in_configured_mode(const NavdataPacket& packet) const;

  bool demo_expected_;
  bool configured_ = false;
};

}  // namespace labo::ardrone2
