#include "drone/tello/tello_wire.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace labo::tello {

namespace {
constexpr double kDegPerRad = 180.0 / std::numbers::pi;
constexpr double kG = 9.80665;
constexpr double kStandardPressurePa = 101325.0;

int stick(double v, int limit) {
  return static_cast<int>(std::lround(std::clamp(v, -1.0, 1.0) * limit));
}

double wrap_deg(double deg) {
  deg = std::fmod(deg + 180.0, 360.0);
  if (deg < 0) deg += 360.0;
  return deg - 180.0;
}

// The ISA barometric formula: altitude above mean sea level for a static pressure.
double pressure_altitude_m(double pressure_pa) {
  return 44330.0 * (1.0 - std::pow(pressure_pa / kStandardPressurePa, 0.190263));
}
}  // namespace

RcSticks rc_from_move(const MoveCommand& c, int limit_percent) {
  if (!std::isfinite(c.roll) || !std::isfinite(c.pitch) || !std::isfinite(c.gaz) || !std::isfinite(c.yaw_rate))
    return RcSticks{};
  const int limit = std::clamp(limit_percent, 1, kMaxStick);
  return RcSticks{stick(c.roll, limit), stick(c.pitch, limit), stick(c.gaz, limit), stick(-c.yaw_rate, limit)};
}

MoveCommand move_from_rc(const RcSticks& s) {
  auto unit = [](int v) { return std::clamp(static_cast<double>(v) / kMaxStick, -1.0, 1.0); };
  return MoveCommand{unit(s.a), unit(s.b), unit(s.c), -unit(s.d)};
}

void sample_from_state(const TelloState& s, Seconds t, std::uint32_t sequence, int control_state,
                       NavdataSample& out) {
  out.t = t;
  out.sequence = sequence;
  out.state = 0;
  out.control_state = control_state;
  out.battery_percent = s.bat_percent;
  out.roll_rad = s.roll_deg / kDegPerRad;
  // Negations written as 0 - x: a zero stays +0 (printed as 0, not -0, by `labodrone tello-state`).
  out.pitch_rad = 0.0 - s.pitch_deg / kDegPerRad;  // nose up -> nose down
  out.yaw_rad = 0.0 - s.yaw_deg / kDegPerRad;      // clockwise -> counter-clockwise
  out.altitude_m = (s.tof_cm <= kTofMaxCm ? s.tof_cm : s.h_cm) * 0.01;
  out.vx_mps = s.vgx_dmps * 0.1;
  out.vy_mps = 0.0 - s.vgy_dmps * 0.1;  // right -> left
  out.vz_mps = 0.0 - s.vgz_dmps * 0.1;  // down -> up
  out.has_drone_time = false;
  out.drone_time = 0;
}

TelloState state_from_telemetry(const VehicleTelemetry& tel, const EmulatedStateExtras& extras) {
  const NavdataSample& n = tel.nav;
  TelloState s;
  s.pitch_deg = -n.pitch_rad * kDegPerRad;
  s.roll_deg = n.roll_rad * kDegPerRad;
  s.yaw_deg = wrap_deg(-n.yaw_rad * kDegPerRad);
  s.vgx_dmps = n.vx_mps * 10.0;
  s.vgy_dmps = -n.vy_mps * 10.0;
  s.vgz_dmps = -n.vz_mps * 10.0;
  s.templ_c = extras.temperature_c;
  s.temph_c = extras.temperature_c + 2.0;
  s.tof_cm = std::clamp(n.altitude_m * 100.0, 0.0, 10000.0);
  s.h_cm = std::clamp(extras.height_m * 100.0, -10000.0, 10000.0);
  s.bat_percent = std::clamp(std::round(n.battery_percent), 0.0, 100.0);
  s.baro_cm = std::clamp(pressure_altitude_m(tel.pressure_pa) * 100.0, -100000.0, 1000000.0);
  s.time_s = std::clamp(std::floor(extras.motors_s), 0.0, 100000.0);
  s.agx_mg = std::clamp(tel.accel_body_mps2.x() / kG * 1000.0, -16000.0, 16000.0);
  s.agy_mg = std::clamp(-tel.accel_body_mps2.y() / kG * 1000.0, -16000.0, 16000.0);
  s.agz_mg = std::clamp(-tel.accel_body_mps2.z() / kG * 1000.0, -16000.0, 16000.0);
  return s;
}

}  // namespace labo::tello
