// The Tello's state string: parsed with every field bounded, refused with a reason naming the field,
// written back by the emulator's formatter, and converted to LaboDrone's units and signs.
#include <catch2/catch.hpp>
#include <numbers>
#include <string>

#include "drone/tello/tello_state.hpp"
#include "drone/tello/tello_wire.hpp"

using namespace labo;
using namespace labo::tello;

namespace {

// The SDK 2.0 document's layout with the values of a Tello hovering at about 1 m.
constexpr const char* kHovering =
    "pitch:-2;roll:1;yaw:-90;vgx:3;vgy:-1;vgz:0;templ:62;temph:64;tof:98;h:90;bat:81;baro:-57.14;time:14;"
    "agx:17.00;agy:-4.00;agz:-996.00;\r\n";
constexpr const char* kMissionPad = "mid:-1;x:-100;y:-100;z:-100;mpry:-1,-1,-1;";

TelloStateParseResult parse(const std::string& text, TelloState& state) { return TelloStateParser().parse(text, state); }

TelloStateError error_of(const std::string& text) {
  TelloState state;
  return parse(text, state).error;
}

std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  REQUIRE(at != std::string::npos);
  return text.replace(at, from.size(), to);
}

}  // namespace

TEST_CASE("tello: a state string parses into its fields, in the drone's units", "[tello][state]") {
  TelloState s;
  const auto r = parse(kHovering, s);
  REQUIRE(r.ok());
  CHECK_FALSE(s.has_mission_pad);
  CHECK(s.pitch_deg == -2);
  CHECK(s.roll_deg == 1);
  CHECK(s.yaw_deg == -90);
  CHECK(s.vgx_dmps == 3);
  CHECK(s.vgy_dmps == -1);
  CHECK(s.templ_c == 62);
  CHECK(s.temph_c == 64);
  CHECK(s.tof_cm == 98);
  CHECK(s.h_cm == 90);
  CHECK(s.bat_percent == 81);
  CHECK(s.baro_cm == Approx(-57.14));
  CHECK(s.time_s == 14);
  CHECK(s.agz_mg == Approx(-996.0));
  CHECK(r.unknown_fields == 0);

  // A Tello EDU with mission pads prefixes five fields; fields may come in any order.
  REQUIRE(parse(std::string(kMissionPad) + kHovering, s).ok());
  CHECK(s.has_mission_pad);
  CHECK(s.mid == -1);
  CHECK(s.x_cm == -100);
  CHECK(s.mpry_deg[2] == -1);
  REQUIRE(parse("mid:3;x:12;y:-40;z:95;mpry:1,2,93;" + std::string(kHovering), s).ok());
  CHECK(s.mid == 3);
  CHECK(s.mpry_deg[2] == 93);

  // Without the final line break, with spaces after the separators (the SDK 1.3 layout), and with a
  // field a later firmware may add: accepted, the unknown field counted.
  REQUIRE(parse(replaced(kHovering, ";\r\n", ";"), s).ok());
  REQUIRE(parse(replaced(kHovering, "baro:", " baro: "), s).ok());
  const auto extra = parse(std::string(kHovering).insert(0, "wifi:90;"), s);
  REQUIRE(extra.ok());
  CHECK(extra.unknown_fields == 1);
}

TEST_CASE("tello: malformed state strings are refused with the field and what was expected", "[tello][state]") {
  TelloState s;
  CHECK(error_of("") == TelloStateError::Empty);
  CHECK(error_of(std::string(600, 'a')) == TelloStateError::TooLong);
  CHECK(error_of(replaced(kHovering, "bat:81", std::string("bat:8\x01", 6))) == TelloStateError::NotText);
  CHECK(error_of(replaced(kHovering, "agz:-996.00;\r\n", "agz:-99")) == TelloStateError::Unterminated);
  CHECK(error_of(replaced(kHovering, "tof:98", "tof98")) == TelloStateError::MalformedField);
  CHECK(error_of(replaced(kHovering, "tof:98", ":98")) == TelloStateError::MalformedField);
  CHECK(error_of(replaced(kHovering, "tof:98", "tof:98;tof:98")) == TelloStateError::DuplicateField);
  CHECK(error_of(replaced(kHovering, "tof:98", "tof:9x")) == TelloStateError::BadNumber);
  CHECK(error_of(replaced(kHovering, "tof:98", "tof:")) == TelloStateError::BadNumber);
  CHECK(error_of(replaced(kHovering, "baro:-57.14", "baro:nan")) == TelloStateError::BadNumber);
  CHECK(error_of(replaced(kHovering, "baro:-57.14", "baro:1e999")) == TelloStateError::BadNumber);
  CHECK(error_of(replaced(kHovering, "bat:81", "bat:181")) == TelloStateError::OutOfRange);
  CHECK(error_of(replaced(kHovering, "pitch:-2", "pitch:-200")) == TelloStateError::OutOfRange);
  CHECK(error_of(replaced(kHovering, "agz:-996.00;", "")) == TelloStateError::MissingField);
  CHECK(error_of("mid:3;x:1;" + std::string(kHovering)) == TelloStateError::MissingField);
  CHECK(error_of("mid:1;x:1;y:1;z:1;mpry:1,2;" + std::string(kHovering)) == TelloStateError::BadNumber);
  CHECK(error_of("mid:1;x:1;y:1;z:1;mpry:1,2,3,4;" + std::string(kHovering)) == TelloStateError::BadNumber);

  const auto r = parse(replaced(kHovering, "bat:81", "bat:181"), s);
  CHECK(r.detail == "field 'bat': 181 outside [0, 100]");
  CHECK(to_string(r.error) == "tello_state_out_of_range");
  CHECK(parse(replaced(kHovering, "time:14;", ""), s).detail == "missing field 'time'");
  // A refused string leaves the last good state as it was.
  REQUIRE(parse(kHovering, s).ok());
  CHECK_FALSE(parse(replaced(kHovering, "bat:81", "bat:x"), s).ok());
  CHECK(s.bat_percent == 81);
}

TEST_CASE("tello: the emulator's state string parses back to the same values", "[tello][state]") {
  TelloState s;
  s.pitch_deg = 3;
  s.roll_deg = -4;
  s.yaw_deg = 179;
  s.vgx_dmps = 12;
  s.vgy_dmps = -7;
  s.vgz_dmps = 2;
  s.templ_c = 70;
  s.temph_c = 72;
  s.tof_cm = 123;
  s.h_cm = 110;
  s.bat_percent = 55;
  s.baro_cm = 1234.56;
  s.time_s = 42;
  s.agx_mg = -12.5;
  s.agy_mg = 3.25;
  s.agz_mg = -1001.75;
  for (bool pad : {false, true}) {
    s.has_mission_pad = pad;
    s.mid = pad ? 4 : -2;
    s.x_cm = pad ? -30 : 0;
    s.mpry_deg = {1, -2, 45};
    std::string text;
    format_tello_state(s, text);
    CHECK(text.ends_with(";\r\n"));
    TelloState back;
    REQUIRE(TelloStateParser().parse(text, back).ok());
    CHECK(back.has_mission_pad == pad);
    CHECK(back.yaw_deg == s.yaw_deg);
    CHECK(back.vgy_dmps == s.vgy_dmps);
    CHECK(back.baro_cm == Approx(s.baro_cm));
    CHECK(back.agy_mg == Approx(s.agy_mg));
    CHECK(back.time_s == s.time_s);
    if (pad) CHECK(back.mpry_deg[2] == 45);
  }
}

TEST_CASE("tello: a state becomes a navdata sample in SI units and LaboDrone's signs", "[tello][state]") {
  TelloState s;
  REQUIRE(TelloStateParser().parse(kHovering, s).ok());
  NavdataSample n;
  sample_from_state(s, 12.5, 7, 4, n);
  const double rad = std::numbers::pi / 180.0;
  CHECK(n.t == 12.5);
  CHECK(n.sequence == 7);
  CHECK(n.control_state == 4);
  CHECK(n.battery_percent == 81);
  CHECK(n.pitch_rad == Approx(2 * rad));   // the Tello's nose up is LaboDrone's negative pitch
  CHECK(n.roll_rad == Approx(1 * rad));    // right wing down on both
  CHECK(n.yaw_rad == Approx(90 * rad));    // clockwise -90 = counter-clockwise +90
  CHECK(n.altitude_m == Approx(0.98));     // the ToF range
  CHECK(n.vx_mps == Approx(0.3));          // dm/s forward
  CHECK(n.vy_mps == Approx(0.1));          // the Tello's right is LaboDrone's -y
  CHECK(n.vz_mps == Approx(0.0));
  CHECK_FALSE(n.has_drone_time);

  // Beyond the ToF's range the height above the take-off point stands in for it.
  s.tof_cm = 6553;
  sample_from_state(s, 13.0, 8, 4, n);
  CHECK(n.altitude_m == Approx(0.90));

  // The emulator's direction: a vehicle's telemetry gives back the same sample.
  VehicleTelemetry tel;
  tel.nav.pitch_rad = 0.1;
  tel.nav.roll_rad = -0.05;
  tel.nav.yaw_rad = 2.0;
  tel.nav.vx_mps = 0.5;
  tel.nav.vy_mps = -0.3;
  tel.nav.vz_mps = 0.2;
  tel.nav.altitude_m = 1.25;
  tel.nav.battery_percent = 64.4;
  tel.accel_body_mps2 = Eigen::Vector3d(0.0, 0.0, 9.80665);
  const TelloState back = state_from_telemetry(tel, EmulatedStateExtras{1.2, 30.7, 61});
  CHECK(back.agz_mg == Approx(-1000.0));  // at rest the z axis (down) reads -1 g
  CHECK(back.time_s == 30);
  CHECK(back.h_cm == Approx(120));
  sample_from_state(back, 1.0, 1, 3, n);
  CHECK(n.pitch_rad == Approx(0.1));
  CHECK(n.roll_rad == Approx(-0.05));
  CHECK(n.yaw_rad == Approx(2.0));
  CHECK(n.vx_mps == Approx(0.5));
  CHECK(n.vy_mps == Approx(-0.3));
  CHECK(n.vz_mps == Approx(0.2));
  CHECK(n.altitude_m == Approx(1.25));
  CHECK(n.battery_percent == 64);
}

TEST_CASE("tello: sticks map a MoveCommand to rc with limits, and back", "[tello][rc]") {
  // LaboDrone's signs: roll > 0 right, pitch > 0 forward, gaz > 0 up, yaw_rate > 0 counter-clockwise.
  const RcSticks s = rc_from_move(MoveCommand{0.5, -0.25, 1.0, 0.4});
  CHECK(s == RcSticks{50, -25, 100, -40});
  CHECK(rc_from_move(MoveCommand{2.0, -3.0, 0, 0}) == RcSticks{100, -100, 0, 0});  // clipped
  CHECK(rc_from_move(MoveCommand{1.0, 0.5, 0, -1.0}, 40) == RcSticks{40, 20, 0, 40});  // the configured limit
  CHECK(rc_from_move(MoveCommand{std::nan(""), 0.5, 0, 0}).centred());                // not finite: hover
  const MoveCommand back = move_from_rc(RcSticks{50, -25, 100, -40});
  CHECK(back.roll == Approx(0.5));
  CHECK(back.pitch == Approx(-0.25));
  CHECK(back.gaz == Approx(1.0));
  CHECK(back.yaw_rate == Approx(0.4));

  std::string text;
  format_rc(s, text);
  CHECK(text == "rc 50 -25 100 -40");
  RcSticks parsed;
  REQUIRE(parse_rc_arguments(text.substr(3), parsed));
  CHECK(parsed == s);
  CHECK_FALSE(parse_rc_arguments("1 2 3", parsed));
  CHECK_FALSE(parse_rc_arguments("1 2 3 4 5", parsed));
  CHECK_FALSE(parse_rc_arguments("1 2 3 101", parsed));
  CHECK_FALSE(parse_rc_arguments("1 2 x 4", parsed));
  CHECK_FALSE(parse_rc_arguments("", parsed));
}
