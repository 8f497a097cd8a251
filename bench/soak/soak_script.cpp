#include "bench/soak/soak_script.hpp"

#include <algorithm>
#include <cstdio>
#include <iostream>
#include <thread>

#include "core/frames.hpp"
#include "localization/fusion/lab_geometry.hpp"

namespace labo::bench {

using server::AppConfig;
using server::FlightTelemetry;


namespace {

constexpr double kFlightBeforeFault_s = 10;  // a fault in flight: once the drone has really flown
constexpr double kHeartbeatEvery_s = 2;  // as the page does

const char* name_of(PlannedFault::Kind kind) {
  switch (kind) {
    case PlannedFault::Kind::LinkCut: return "link_cut";
    case PlannedFault::Kind::EmulatorRestart: return "emulator_restart";
    case PlannedFault::Kind::LowBattery: return "low_battery";
  }
  return "?";
}

void pause(double s) { std::this_thread::sleep_for(std::chrono::duration<double>(s)); }

// Progress on stderr, so a long soak's log shows what it was doing when something went wrong.
void say(double t, const std::string& text) {
  char stamp[32];
  std::snprintf(stamp, sizeof stamp, "[soak %6.0f s] ", t);
  std::cerr << stamp << text << std::endl;
}

}  // namespace

std::vector<PlannedFault> plan_faults(double total_s) {
  using K = PlannedFault::Kind;
  // A short cut (the flight software hovers and goes on), a restart, a cut longer than
  // control.safety.link_loss_land_s (it lands), then the nearly empty battery.
  std::vector<PlannedFault> plan{{K::LinkCut, 0.15 * total_s, 3},
                                 {K::EmulatorRestart, 0.3 * total_s, 3},
                                 {K::LinkCut, 0.45 * total_s, 8},
                                 {K::LowBattery, 0.6 * total_s, 0}};
  if (total_s >= 600) {  // a long soak has time for a restart that outlasts the link-loss landing
    plan.push_back({K::EmulatorRestart, 0.72 * total_s, 7});
    plan.push_back({K::LinkCut, 0.85 * total_s, 3});
  }
  return plan;
}

SoakScript::SoakScript(SoakServer& server, SoakWatch& watch, boost::asio::io_context& io, const AppConfig& config,
                       std::vector<Student> students, Student admin, ScriptOptions options)
    : server_(server), watch_(watch), io_(io), config_(config), students_(std::move(students)), admin_(std::move(admin)),
      options_(options),
      plan_(plan_faults(options.total_s)), applied_(plan_.size(), false) {
  for (const auto& i : fusion::lab_geometry_from(config.lab).instruments) instruments_.push_back(i.id);
  if (students_.empty() || instruments_.empty()) throw std::runtime_error("soak: no student or no instrument to inspect");
}

void SoakScript::run() {
  for (int r = 0;; ++r) {
    const bool faults_left = std::find(applied_.begin(), applied_.end(), false) != applied_.end();
    // Past the time, rounds go on for the faults not yet applied, for at most half the time more.
    const double extra_s = std::min(600.0, 0.5 * options_.total_s);
    if (now() >= options_.total_s && (!faults_left || now() >= options_.total_s + extra_s)) break;
    round(r);
  }
  if (queued_) queued_->close();
  look_after_faults(true);
}

std::shared_ptr<SoakClient> SoakScript::queue_for_control(const Student& student) {
  auto client = SoakClient::connect(io_, server_.port(), student.cookie);
  client->send({{"type", "request_control"}});
  return client;
}

// Between rounds, on the ground: after a crash what the lab would do; else the nearly empty battery
// when it is due, or a fresh one when the drone is down to the swap level.
void SoakScript::ready_the_drone(bool low_battery) {
  const double low_percent = config_.control.safety.low_battery_percent + 5;  // about 40 s of flight
  DroneTruth truth = server_.drone().truth();
  const double unobserved_s = server_.flight().telemetry().unobserved_flight_s;
  if (!truth.airborne && truth.phase != "emergency" && !crash_ && unobserved_s > 0) {
    set_on_platform(truth, unobserved_s);
    truth = server_.drone().truth();
  }
  const double full_percent = config_.sim.lab.dynamics.battery.start_percent;
  if (!crash_ && truth.phase == "emergency") crash_ = truth;  // it crashed outside a mission
  if (crash_) {
    // What the lab does after a crash (which itself fails the soak): the drone back on its
    // platform with a fresh battery, the flight software restarted (its pose is wherever the tumble
    // left it, and nothing re-anchors it).
    say(now(), "the drone hit " + crash_->crash_reason + ": back on its platform, the flight software restarted");
    DroneTruth on_platform;
    on_platform.position_m = config_.lab.T_world_base.translation();
    on_platform.yaw_rad = ypr_from_rotation(config_.lab.T_world_base.linear())[0];
    swap_battery(low_battery ? low_percent : full_percent, on_platform, true);
    crash_.reset();
  } else if (truth.airborne) {
    // Never swapped in flight: the round after a drone that would not land tries again.
  } else if (low_battery) {
    swap_battery(low_percent, truth);
  } else if (truth.battery_percent < options_.battery_swap_below_percent) {
    swap_battery(full_percent, truth);
  }
}

void SoakScript::round(int index) {
  ++rounds_;
  const auto mission = static_cast<Mission>(index % 3);
  bool low_battery = false;
  for (std::size_t i = 0; i < plan_.size(); ++i) {
    if (!applied_[i] && plan_[i].kind == PlannedFault::Kind::LowBattery && plan_[i].due_s <= now()) {
      applied_[i] = low_battery = true;
      break;
    }
  }
  ready_the_drone(low_battery);

  auto client = queued_ ? queued_ : queue_for_control(students_[index % students_.size()]);
  queued_.reset();
  const double asked = now();
  while (!client->view().controlling && now() - asked < 30) {
    heartbeats(client.get());
    pause(0.1);
  }
  if (!client->view().controlling) {
    results_.push_back("round " + std::to_string(index) + ": control was not granted in 30 s");
    client->close();
    return;
  }
  queued_ = queue_for_control(students_[(index + 1) % students_.size()]);  // waits in the queue

  nlohmann::json command{{"type", "command"}, {"command", "find_teacher"}};
  if (mission != Mission::FindTeacher) {
    command["command"] = "inspect";
    command["instrument"] = mission == Mission::InspectFirst ? instruments_.front() : instruments_.back();
    command["hold_s"] = 5;
  }
  say(now(), "round " + std::to_string(index) + ": " + students_[index % students_.size()].name + " asks for " +
                 command.dump() + " (battery " + std::to_string(static_cast<int>(server_.drone().truth().battery_percent)) +
                 " %)");
  const std::uint64_t ended_before = client->view().missions_ended, safety_before = client->view().safety_events;
  const std::size_t low_record = faults_.size();
  if (low_battery) faults_.push_back({"low_battery", now(), 0, false, "", ""});
  low_battery_round_ = low_battery;
  if (!issue(*client, command)) {
    ++refused_;
    results_.push_back(command.value("command", "") + " refused: " + client->view().last_ack_reason);
  } else {
    ++accepted_;
    fly(*client, mission, ended_before, safety_before);
  }
  land_if_flying(*client);
  low_battery_round_ = false;
  if (low_battery) {
    FaultRecord& f = faults_[low_record];
    f.duration_s = now() - f.at_s;
    f.after = drone_activity(server_.drone().truth(), server_.flight().telemetry());
    if (client->view().safety_events > safety_before) f.detail = client->view().last_safety;
    say(now(), "low battery: then " + f.after + " (" + f.detail + ")");
  }
  client->send({{"type", "release_control"}});
  client->close();
}

bool SoakScript::issue(SoakClient& client, const nlohmann::json& command) {
  // Refused while the link comes back after a fault: asked again, as a student would.
  const double start = now();
  while (now() - start < 30) {
    nlohmann::json c = command;
    const int id = next_command_id_++;
    c["id"] = id;
    client.send(c);
    const double sent = now();
    while (client.view().last_ack_id != id && now() - sent < 5) {
      tick(client);
      pause(0.05);
    }
    const ClientView v = client.view();
    if (v.last_ack_id == id && v.last_ack_accepted) return true;
    // Refused because the drone landed where its place is not confirmed, after the round's check
    // (it was still coming down): the lab does what it does between rounds.
    const DroneTruth truth = server_.drone().truth();
    const double unobserved_s = server_.flight().telemetry().unobserved_flight_s;
    if (v.last_ack_id == id && !truth.airborne && unobserved_s > 0) set_on_platform(truth, unobserved_s);
    pause(2);
  }
  return false;
}

void SoakScript::fly(SoakClient& client, Mission mission, std::uint64_t ended_before, std::uint64_t safety_before) {
  const double start = now();
  double following_since = -1;
  bool land_sent = false;
  std::string result;
  bool running_seen = false;
  while (now() - start < options_.mission_timeout_s) {
    tick(client);
    const ClientView v = client.view();
    if (v.missions_ended > ended_before) {
      result = v.last_ended;
      break;
    }
    const DroneTruth truth = server_.drone().truth();
    if (truth.phase == "emergency") {
      // The drone crashed (SoakWatch counts it): once it lies still the student presses the
      // emergency stop, as on the page, so the flight software knows the motors are off (the toggle
      // also clears the drone's emergency on the ground).
      crash_ = truth;
      pause(3);
      issue(client, {{"type", "command"}, {"command", "emergency_stop"}});
      pause(1);  // the toggle is sent for a few cycles: not into the next drone
      result = "crashed into " + truth.crash_reason;
      break;
    }
    // A mission the safety monitor ends says so in a "safety: ..." event, not in an "ended" one:
    // the telemetry's mission going back to idle tells the end.
    running_seen = running_seen || v.mission != "idle";
    if (running_seen && v.mission == "idle" && !land_sent) {
      result = "ended: " + (v.safety_events > safety_before ? v.last_safety : std::string("no reason given"));
      break;
    }
    if (mission == Mission::FindTeacher && v.stage.find("face-follow") != std::string::npos && following_since < 0)
      following_since = now();
    if (following_since >= 0 && !land_sent && now() - following_since >= options_.follow_s) {
      land_sent = issue(client, {{"type", "command"}, {"command", "land"}});
      result = land_sent ? "followed the teacher, then landed when asked" : "land refused: " + v.last_ack_reason;
    }
    if (land_sent && !server_.drone().truth().airborne) break;
    pause(0.2);
  }
  if (result.empty()) result = "timed out in stage '" + client.view().stage + "'";
  const bool ok = mission == Mission::FindTeacher ? land_sent : result.find("ended: succeeded") != std::string::npos;
  succeeded_ += ok ? 1 : 0;
  results_.push_back(result);
  say(now(), result);
}

void SoakScript::land_if_flying(SoakClient& client) {
  // A mission that ended in the air (failed, or a fault ended it) leaves the drone held: the student
  // lands it before handing over.
  const double start = now();
  bool asked = false;
  while (server_.drone().truth().airborne && now() - start < 60) {
    if (!asked && now() - start > 5) asked = issue(client, {{"type", "command"}, {"command", "land"}});
    tick(client);
    pause(0.2);
  }
}

void SoakScript::heartbeats(SoakClient* controlling) {
  // The queued student may be granted control at any time and must then keep it alive too.
  if (now() - last_heartbeat_ < kHeartbeatEvery_s) return;
  if (controlling) controlling->send({{"type", "heartbeat"}});
  if (queued_) queued_->send({{"type", "heartbeat"}});
  last_heartbeat_ = now();
}

void SoakScript::tick(SoakClient& client) {
  heartbeats(&client);
  const bool airborne = server_.drone().truth().airborne;
  if (!airborne) flying_since_ = -1;
  else if (flying_since_ < 0) flying_since_ = now();
  apply_in_flight_faults();
  look_after_faults(false);
}

void SoakScript::apply_in_flight_faults() {
  // One fault at a time: the next waits until the drone has been looked at after the last.
  if (flying_since_ < 0 || now() - flying_since_ < kFlightBeforeFault_s || !looks_.empty() || low_battery_round_) return;
  for (std::size_t i = 0; i < plan_.size(); ++i) {
    const PlannedFault& p = plan_[i];
    if (applied_[i] || p.kind == PlannedFault::Kind::LowBattery || p.due_s > now()) continue;
    applied_[i] = true;
    faults_.push_back({name_of(p.kind), now(), p.duration_s, true, "", ""});
    say(now(), std::string(name_of(p.kind)) + " for " + std::to_string(p.duration_s) + " s, in flight");
    if (p.kind == PlannedFault::Kind::LinkCut) {
      server_.relay().cut_for(p.duration_s);
    } else {
      server_.drone().stop();
      pause(p.duration_s);  // the heartbeats wait too: shorter than control.heartbeat_timeout_s
      server_.drone().start();
    }
    const double over = p.kind == PlannedFault::Kind::LinkCut ? now() + p.duration_s : now();
    looks_.push_back({faults_.size() - 1, over + options_.settle_s});
    return;
  }
}

void SoakScript::look_after_faults(bool now_all) {
  for (auto it = looks_.begin(); it != looks_.end();) {
    if (!now_all && now() < it->at_s) {
      ++it;
      continue;
    }
    faults_[it->fault].after = drone_activity(server_.drone().truth(), server_.flight().telemetry());
    say(now(), faults_[it->fault].kind + " over: then " + faults_[it->fault].after);
    it = looks_.erase(it);
  }
}

void SoakScript::swap_battery(double start_percent, const DroneTruth& where, bool restart_flight) {
  put_drone(start_percent, where, restart_flight);
  ++battery_swaps_;
  say(now(), "battery swapped: " + std::to_string(static_cast<int>(start_percent)) + " %");
}

void SoakScript::put_drone(double start_percent, const DroneTruth& where, bool restart_flight) {
  AppConfig c = config_;
  c.sim.lab.dynamics.battery.start_percent = start_percent;
  heartbeats(nullptr);
  server_.drone().stop();
  server_.drone().replace_lab(c, where.position_m.head<2>(), where.yaw_rad);
  heartbeats(nullptr);
  if (restart_flight) server_.restart_flight();
  heartbeats(nullptr);
  server_.drone().start();
  // The driver notices the new drone (navdata silent, then a new session): wait for the flight
  // software to read the new battery before asking for a mission.
  const double start = now();
  while (now() - start < 30) {
    heartbeats(nullptr);  // the next student holds control already, between rounds
    const FlightTelemetry t = server_.flight().telemetry();
    if (t.link_state == "connected" && std::abs(t.battery_percent - start_percent) < 3) break;
    pause(0.2);
  }
}

void SoakScript::set_on_platform(const DroneTruth& truth, double unobserved_s) {
  say(now(), "the drone landed where its place is not confirmed (" + std::to_string(unobserved_s) +
                 " s of flight unseen): the lab carries it to its platform");
  DroneTruth on_platform = truth;
  on_platform.position_m = config_.lab.T_world_base.translation();
  on_platform.yaw_rad = ypr_from_rotation(config_.lab.T_world_base.linear())[0];
  put_drone(truth.battery_percent, on_platform, false);
  const HttpAnswer a = http_request(server_.port(), "POST", "/api/drone/set-down", "", admin_.cookie);
  say(now(), "POST /api/drone/set-down as " + admin_.name + ": " + std::to_string(a.status) + " " + a.body);
  if (a.status == 200) ++set_downs_;
}

void SoakScript::report(SoakSummary& s) const {
  s.rounds = rounds_;
  s.missions_accepted = accepted_;
  s.missions_succeeded = succeeded_;
  s.missions_refused = refused_;
  s.mission_results = results_;
  s.faults = faults_;
  s.battery_swaps = battery_swaps_;
  s.set_downs = set_downs_;
}

}  // namespace labo::bench
