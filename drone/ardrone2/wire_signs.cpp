#include "drone/ardrone2/wire_signs.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace labo::ardrone2 {

namespace {
constexpr double kRadPerMilliDeg = std::numbers::pi / 180.0 / 1000.0;
float unit(double v) { return static_cast<float>(std::clamp(v, -1.0, 1.0)); }
}  // namespace

WirePcmd move_to_wire(const MoveCommand& c) {
  if (!std::isfinite(c.roll) || !std::isfinite(c.pitch) || !std::isfinite(c.gaz) || !std::isfinite(c.yaw_rate))
    return WirePcmd{};
  return WirePcmd{false, unit(c.roll), unit(-c.pitch), unit(c.gaz), unit(-c.yaw_rate)};
}

MoveCommand move_from_wire(const WirePcmd& c) {
  if (c.hover) return MoveCommand{};
  return MoveCommand{unit(c.roll), unit(-c.pitch), unit(c.gaz), unit(-c.yaw)};
}

bool sample_from_packet(const NavdataPacket& p, Seconds t, NavdataSample& s) {
  s.t = t;
  s.sequence = p.sequence;
  s.state = p.state;
  if (p.has(kTagTime)) {
    s.has_drone_time = true;
    s.drone_time = navdata_time_seconds(static_cast<std::uint32_t>(p.option(kTagTime).raw[0]));
  } else {
    s.has_drone_time = false;
  }
  if (!p.has(kTagDemo)) return false;
  // Index order of kDemo in navdata_schema.cpp: ctrl_state, vbat, theta, phi, psi, altitude, vx, vy, vz.
  const auto& d = p.option(kTagDemo).raw;
  s.control_state = control_state_major(static_cast<std::uint32_t>(d[0]));
  s.battery_percent = d[1];
  s.pitch_rad = -d[2] * kRadPerMilliDeg;  // theta nose-up -> pitch nose-down
  s.roll_rad = d[3] * kRadPerMilliDeg;
  s.yaw_rad = -d[4] * kRadPerMilliDeg;    // psi clockwise -> yaw counter-clockwise
  s.altitude_m = d[5] * 1e-3;
  s.vx_mps = d[6] * 1e-3;
  s.vy_mps = -d[7] * 1e-3;  // right -> left
  s.vz_mps = -d[8] * 1e-3;  // down -> up
  return true;
}

void sample_to_packet(const NavdataSample& s, NavdataPacket& p) {
  if (!p.has(kTagDemo)) p.add_option(kTagDemo);
  auto& d = p.option(kTagDemo).raw;
  d[0] = static_cast<double>(static_cast<std::uint32_t>(s.control_state) << 16);
  d[1] = std::clamp(std::round(s.battery_percent), 0.0, 100.0);
  d[2] = -s.pitch_rad / kRadPerMilliDeg;
  d[3] = s.roll_rad / kRadPerMilliDeg;
  d[4] = -s.yaw_rad / kRadPerMilliDeg;
  d[5] = std::round(s.altitude_m * 1e3);
  d[6] = s.vx_mps * 1e3;
  d[7] = -s.vy_mps * 1e3;
  d[8] = -s.vz_mps * 1e3;
  if (s.has_drone_time) {
    if (!p.has(kTagTime)) p.add_option(kTagTime);
    const double t = std::max(0.0, s.drone_time);
    const auto secs = static_cast<std::uint32_t>(t) & 0x7FFu;
    const auto usecs = static_cast<std::uint32_t>((t - std::floor(t)) * 1e6) & 0x1FFFFFu;
    p.option(kTagTime).raw[0] = static_cast<double>((secs << 21) | usecs);
  }
}

}  // namespace labo::ardrone2
