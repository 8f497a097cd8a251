#pragma once
// The one place where the AR.Drone's wire sign conventions meet LaboDrone's (docs/ardrone2.md).
// AR.Drone: PCMD roll<0 = left, pitch<0 = forward, gaz>0 = up, yaw>0 = clockwise; navdata phi>0 =
// right wing down, theta>0 = nose up, psi>0 = clockwise, vx>0 = forward, vy>0 = right, vz>0 = down,
// all in millidegrees and mm, mm/s. LaboDrone (drone/drone_link.hpp): roll>0 = right, pitch>0 =
// nose down (forward), gaz>0 = up, yaw>0 = counter-clockwise; body x forward, y left, z up; SI units.
// ArdroneLink uses the from_wire directions, ArdroneEmulator the to_wire ones.
#include "drone/ardrone2/at_command.hpp"
#include "drone/ardrone2/navdata_packet.hpp"
#include "drone/drone_link.hpp"

namespace labo::ardrone2 {

// Clips to [-1, 1]; non-finite values give a hover.
WirePcmd move_to_wire(const MoveCommand& command);
MoveCommand move_from_wire(const WirePcmd& command);

// Demo option (+ time when present) of a packet into a sample in SI units and LaboDrone signs.
// Returns false when the packet has no demo option (bootstrap packets): only header fields are set.
bool sample_from_packet(const NavdataPacket& packet, Seconds t, NavdataSample& sample);
// The inverse for the emulator: fills the demo option (and `time` when has_drone_time).
void sample_to_packet(const NavdataSample& sample, NavdataPacket& packet);

}  // namespace labo::ardrone2
