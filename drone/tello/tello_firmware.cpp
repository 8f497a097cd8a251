#include "drone/tello/tello_firmware.hpp"

#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>

#include <opencv2/imgproc.hpp>

#include "drone/drone_link.hpp"
#include "drone/tello/tello_camera_switch.hpp"

namespace labo::tello {

namespace {

constexpr double kAirDensity = 1.225;  // kg/m³, for the height above the take-off point
constexpr double kG = 9.80665;

constexpr std::array<std::string_view, 5> kUnflownCommands = {"jump", "mon", "moff", "mdirection", "wifi"};

bool parse_int(std::string_view text, int& value) {
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  return !text.empty() && ec == std::errc() && end == text.data() + text.size();
}

std::string number_text(double v, const char* format) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), format, v);
  return buf;
}

}  // namespace

TelloFirmware::TelloFirmware(TelloFirmwareSettings settings, ardrone2::LinkCounters& counters)
    : settings_(settings), counters_(counters) {}

bool TelloFirmware::take_stream_restart() {
  const bool restart = stream_restart_;
  stream_restart_ = false;
  return restart;
}

std::optional<TelloFirmware::Reply> TelloFirmware::command(std::string_view text, EmulatedVehicle& vehicle, Seconds t) {
  const std::size_t space = text.find(' ');
  const std::string_view word = text.substr(0, space);
  const std::string_view args = space == std::string_view::npos ? std::string_view() : text.substr(space + 1);
  if (word == "command") {
    if (!sdk_mode_) counters_.add("sdk_mode_entered");
    sdk_mode_ = true;
  }
  if (!sdk_mode_) {
    counters_.add("commands_before_sdk_mode");  // a Tello outside SDK mode ignores text
    return std::nullopt;
  }
  last_command_t_ = t;
  vehicle.advance_to(t);
  return handle(word, args, vehicle, t);
}

std::optional<TelloFirmware::Reply> TelloFirmware::handle(std::string_view word, std::string_view args,
                                                          EmulatedVehicle& vehicle, Seconds t) {
  if (word == "rc") return rc(args, vehicle, t);
  if (word == "emergency") {
    if (!vehicle.telemetry().emergency) vehicle.emergency(t);
    motion_ = Motion::None;  // a take-off, landing or move under way is never answered
    move_.reset();
    counters_.add("emergencies");
    return Reply{"ok", t};
  }
  if (motion_ == Motion::Moving && word == "stop" && args.empty()) {
    // "stop" works at any time: the move ends unfinished ("error", in order), then stop's "ok".
    move_.reset();
    motion_ = Motion::None;
    vehicle.move(MoveCommand{}, true, t);
    counters_.add("moves_stopped");
    deferred_ = after_delay("ok", t);
    return Reply{"error", t};
  }
  if (motion_ != Motion::None) {
    counters_.add("busy_refusals");
    return after_delay("error", t);
  }
  const VehicleTelemetry tel = vehicle.telemetry();
  if (const MoveParse move = parse_distance_move(word, args, speed_cmps_); move.is_move) return start_move(move, tel, t);
  if (word == "command") return after_delay("ok", t);
  if (word == "takeoff" && args.empty()) {
    if (tel.flying) return after_delay("error", t);
    if (tel.emergency) vehicle.emergency(t);  // motors were cut: the toggle re-arms them on the ground
    takeoff_pressure_pa_ = tel.pressure_pa;
    vehicle.takeoff(t);
    motion_ = Motion::TakingOff;
    motion_since_ = t;
    return std::nullopt;
  }
  if (word == "land" && args.empty()) {
    if (!tel.flying) return after_delay("error", t);
    vehicle.land(t);
    motion_ = Motion::Landing;
    motion_since_ = t;
    return std::nullopt;
  }
  if (word == "stop" && args.empty()) {
    vehicle.move(MoveCommand{}, true, t);
    return after_delay("ok", t);
  }
  if ((word == "streamon" || word == "streamoff") && args.empty()) {
    stream_restart_ = word == "streamon" && !streaming_;
    streaming_ = word == "streamon";
    return after_delay("ok", t);
  }
  if (word == "speed" && !args.empty()) {
    int speed = 0;
    if (!parse_int(args, speed) || speed < 10 || speed > 100) {
      counters_.add("bad_arguments");
      return after_delay("error", t);
    }
    speed_cmps_ = speed;
    return after_delay("ok", t);
  }
  if (word == "downvision") return downvision(args, t);
  if (word.ends_with('?') && args.empty()) {
    if (auto reply = read(word, tel, t)) return reply;
  }
  for (std::string_view unflown : kUnflownCommands) {
    if (word == unflown) {
      counters_.add("unflown_commands");
      return after_delay("error", t);
    }
  }
  counters_.bad_input("unknown_command", t, std::string(word) + " (expected an SDK 2.0 command)");
  return after_delay("error", t);
}

std::optional<TelloFirmware::Reply> TelloFirmware::downvision(std::string_view args, Seconds t) {
  if (!settings_.downvision) {
    counters_.add("downvision_unsupported");  // a plain Tello: no downward camera to stream
    return after_delay("error", t);
  }
  if (args != "0" && args != "1") {
    counters_.bad_input("bad_arguments", t, "downvision " + std::string(args) + " (expected 0 or 1)");
    return after_delay("error", t);
  }
  const bool down = args == "1";
  if (down != down_vision_ && streaming_) stream_restart_ = true;  // a new picture size: the stream starts over
  down_vision_ = down;
  counters_.add(down ? "downvision_on" : "downvision_off");
  return after_delay("ok", t);
}

void TelloFirmware::render_stream(EmulatedVehicle& vehicle, cv::Mat& bgr) {
  if (!down_vision_) {
    vehicle.render(CameraId::Front, bgr);
    return;
  }
  vehicle.render(CameraId::Bottom, down_render_);
  if (down_render_.empty() || down_render_.type() != CV_8UC3) {
    bgr.release();  // a scheduled video dropout: no frame
    return;
  }
  const cv::Size size(kDownvisionWidth, kDownvisionHeight);
  const cv::Mat* src = &down_render_;
  if (down_render_.size() != size) {
    cv::resize(down_render_, down_sized_, size, 0, 0, cv::INTER_AREA);
    src = &down_sized_;
  }
  cv::cvtColor(*src, down_grey_, cv::COLOR_BGR2GRAY);  // the downward camera sees in grey only
  cv::cvtColor(down_grey_, bgr, cv::COLOR_GRAY2BGR);
}

std::optional<TelloFirmware::Reply> TelloFirmware::start_move(const MoveParse& move, const VehicleTelemetry& tel, Seconds t) {
  if (!move.plan) {
    counters_.add("move_refused");
    return after_delay("error " + move.error, t);
  }
  if (!tel.flying) {
    counters_.add("move_refused");
    return after_delay("error not flying", t);
  }
  if (move.plan->flip && tel.nav.battery_percent < kMinFlipBatteryPercent) {
    counters_.add("move_refused");
    return after_delay("error battery below 50 %", t);
  }
  counters_.add(move.plan->flip ? "flips" : "moves");
  move_.emplace(*move.plan, odometry_, t);
  motion_ = Motion::Moving;
  motion_since_ = t;
  return std::nullopt;  // answered once done (advance)
}

// One step of the move: its sticks to the vehicle; "ok" once done, "error" when out of time.
std::optional<TelloFirmware::Reply> TelloFirmware::fly_move(EmulatedVehicle& vehicle, Seconds t) {
  MoveCommand sticks;
  const MoveFlight::Status status = move_->step(odometry_, t, sticks);
  if (status == MoveFlight::Status::Flying) {
    vehicle.move(sticks, false, t);
    return std::nullopt;
  }
  vehicle.move(MoveCommand{}, true, t);
  move_.reset();
  motion_ = Motion::None;
  last_command_t_ = t;  // the watchdog counts from the end of the command
  if (status == MoveFlight::Status::TimedOut) counters_.add("moves_timed_out");
  return Reply{status == MoveFlight::Status::Done ? "ok" : "error", t};
}

// Dead reckoning as the drone's own vision positioning gives it: the velocities over the ground
// integrated in the heading, the altitude and heading as measured.
void TelloFirmware::update_odometry(const VehicleTelemetry& tel, Seconds t) {
  const double dt = last_advance_t_ >= 0 ? t - last_advance_t_ : 0.0;
  const double c = std::cos(tel.nav.yaw_rad), s = std::sin(tel.nav.yaw_rad);
  odometry_.position_m.x() += (c * tel.nav.vx_mps - s * tel.nav.vy_mps) * dt;
  odometry_.position_m.y() += (s * tel.nav.vx_mps + c * tel.nav.vy_mps) * dt;
  odometry_.position_m.z() = tel.nav.altitude_m;
  odometry_.yaw_rad = tel.nav.yaw_rad;
  odometry_.velocity_body_mps = {tel.nav.vx_mps, tel.nav.vy_mps, tel.nav.vz_mps};
}

std::optional<TelloFirmware::Reply> TelloFirmware::rc(std::string_view args, EmulatedVehicle& vehicle, Seconds t) {
  RcSticks s;
  if (!parse_rc_arguments(args, s)) {
    counters_.bad_input("rc_malformed", t, "rc " + std::string(args) + " (expected 4 integers in [-100, 100])");
    return std::nullopt;
  }
  counters_.add("rc_received");
  if (motion_ == Motion::Moving) {
    counters_.add("rc_ignored_during_move");  // the move flies the vehicle until it is done or stopped
    return std::nullopt;
  }
  vehicle.move(move_from_rc(s), s.centred(), t);
  return std::nullopt;
}

std::optional<TelloFirmware::Reply> TelloFirmware::read(std::string_view word, const VehicleTelemetry& tel,
                                                        Seconds t) const {
  if (word == "battery?") return after_delay(number_text(std::round(tel.nav.battery_percent), "%.0f"), t);
  if (word == "speed?") return after_delay(number_text(speed_cmps_, "%.1f"), t);
  if (word == "time?") return after_delay(number_text(std::floor(motors_s_), "%.0fs"), t);
  if (word == "wifi?") return after_delay(number_text(std::round(tel.wifi_link_quality * 90.0), "%.0f"), t);
  if (word == "sdk?") return after_delay("20", t);
  if (word == "sn?") return after_delay("LABODRONEEMU0001", t);
  return std::nullopt;
}

std::optional<TelloFirmware::Reply> TelloFirmware::advance(EmulatedVehicle& vehicle, Seconds t) {
  vehicle.advance_to(t);
  const VehicleTelemetry tel = vehicle.telemetry();
  if (last_advance_t_ >= 0 && tel.flying) motors_s_ += t - last_advance_t_;
  update_odometry(tel, t);
  last_advance_t_ = t;
  height_m_ = takeoff_pressure_pa_ > 0 ? (takeoff_pressure_pa_ - tel.pressure_pa) / (kAirDensity * kG) : 0.0;
  if (deferred_) {
    std::optional<Reply> reply = std::move(deferred_);
    deferred_.reset();
    return reply;
  }
  if (motion_ == Motion::Moving) return fly_move(vehicle, t);
  if (motion_ == Motion::None) {
    if (sdk_mode_ && tel.flying && t - last_command_t_ > settings_.watchdog_s) {
      counters_.add("watchdog_landings");
      vehicle.land(t);
      last_command_t_ = t;  // one landing per silence
    }
    return std::nullopt;
  }
  const int cs = tel.nav.control_state;
  const bool done = motion_ == Motion::TakingOff ? control_state::follows_commands(cs)
                                                 : (cs == control_state::kLanded && !tel.flying);
  if (done || t - motion_since_ > settings_.motion_timeout_s) {
    motion_ = Motion::None;
    return Reply{done ? "ok" : "error", t};
  }
  return std::nullopt;
}

TelloState TelloFirmware::state(const VehicleTelemetry& telemetry) const {
  EmulatedStateExtras extras;
  extras.height_m = height_m_;
  extras.motors_s = motors_s_;
  extras.temperature_c = 55.0 + std::min(30.0, motors_s_ / 20.0);  // warms up in flight
  return state_from_telemetry(telemetry, extras);
}

}  // namespace labo::tello
