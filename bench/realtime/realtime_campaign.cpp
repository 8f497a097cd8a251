#include "bench/realtime/realtime_campaign.hpp"

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <mutex>
#include <numbers>
#include <stdexcept>
#include <thread>

#include "localization/fusion/lab_geometry.hpp"
#include "server/app_config.hpp"
#include "server/runtime/drone_backend.hpp"

namespace labo::bench {

using server::AppConfig;
using server::CommandVerdict;
using server::DroneSpec;
using server::FlightEvent;
using server::FlightEventSink;
using server::FlightService;
using server::MissionCommand;
using server::MissionCommandKind;
using server::WireFrame;
using server::load_app_config;
using server::make_drone_backend;

namespace {

using WallClock = std::chrono::steady_clock;

// A text field of the trace: quoted, its own quotes made single (stages and log lines hold commas).
std::string csv_text(std::string text) {
  for (char& c : text)
    if (c == '"') c = '\'';
  return '"' + text + '"';
}

// A CSV of the missions as they flew (RealtimeCampaignOptions::trace_file): telemetry rows and log
// lines, each with the seconds since the campaign began. Shared by the sampler and the runtime's
// threads, hence the lock.
class MissionTrace {
 public:
  explicit MissionTrace(const std::string& file) {
    if (file.empty()) return;
    out_.open(file);
    if (!out_) throw std::runtime_error("--trace " + file + ": cannot write");
    out_ << "t_s,seed,round,mission,stage,source,slam_state,slam_keyframes,x_m,y_m,z_m,yaw_deg,"
            "true_x_m,true_y_m,true_z_m,true_yaw_deg,battery_percent,link,flying,event\n";
  }
  void set_run(unsigned seed, int round) {
    std::lock_guard lock(mutex_);
    seed_ = seed;
    round_ = round;
  }
  void sample(const server::FlightTelemetry& t) {
    if (!out_.is_open()) return;
    std::lock_guard lock(mutex_);
    constexpr double kDeg = 180.0 / std::numbers::pi;
    char buf[256];
    std::snprintf(buf, sizeof buf, "%.2f,%u,%d,", now(), seed_, round_);
    out_ << buf << t.mission << ',' << csv_text(t.stage) << ',' << server::to_string(t.source) << ',' << t.slam_state;
    std::snprintf(buf, sizeof buf, ",%d,%.3f,%.3f,%.3f,%.1f,", t.slam_keyframes, t.pose.x_m, t.pose.y_m, t.pose.z_m,
                  t.pose.yaw_rad * kDeg);
    out_ << buf;
    if (t.ground_truth)
      std::snprintf(buf, sizeof buf, "%.3f,%.3f,%.3f,%.1f,", t.ground_truth->x_m, t.ground_truth->y_m,
                    t.ground_truth->z_m, t.ground_truth->yaw_rad * kDeg);
    else
      std::snprintf(buf, sizeof buf, ",,,,");
    out_ << buf << t.battery_percent << ',' << t.link_state << ',' << (t.flying ? 1 : 0) << ",\n";
  }
  void event(const server::FlightEvent& e) {
    if (!out_.is_open()) return;
    std::lock_guard lock(mutex_);
    out_ << now() << ',' << seed_ << ',' << round_ << ',' << e.mission << ',' << csv_text(e.stage)
         << ",,,,,,,,,,,,,,," << csv_text(e.kind + ": " + (e.message.empty() ? e.stage : e.message)) << '\n';
  }

 private:
  double now() const { return std::chrono::duration<double>(WallClock::now() - start_).count(); }
  std::mutex mutex_;
  std::ofstream out_;
  WallClock::time_point start_ = WallClock::now();
  unsigned seed_ = 0;
  int round_ = 0;
};

// The mission's log lines and stage changes, as the web server would receive them.
class EventLog final : public FlightEventSink {
 public:
  explicit EventLog(MissionTrace& trace) : trace_(trace) {}
  void on_frame(const WireFrame&) override {}
  void on_flight_event(const FlightEvent& e) override {
    trace_.event(e);
    std::lock_guard lock(mutex_);
    if (e.kind == "stage") stage_ = e.stage;
    if (e.kind == "log" && e.message.find("' ended: ") != std::string::npos) ended_ = e.message;
  }
  // Forgets the last mission's end, before the next one is asked for.
  void next_mission() {
    std::lock_guard lock(mutex_);
    ended_.clear();
  }
  std::string ended() const {
    std::lock_guard lock(mutex_);
    return ended_;
  }
  std::string stage() const {
    std::lock_guard lock(mutex_);
    return stage_;
  }

 private:
  MissionTrace& trace_;
  mutable std::mutex mutex_;
  std::string ended_, stage_;
};

double seconds_since(WallClock::time_point start) { return std::chrono::duration<double>(WallClock::now() - start).count(); }

bool wait_for(const std::function<bool()>& done, double timeout_s) {
  const auto start = WallClock::now();
  while (!done()) {
    if (seconds_since(start) > timeout_s) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return true;
}

// Samples the stage every 50 ms for `seconds`: `following` gets the share of samples in stage
// "3 face-follow" itself (a lost face's phases and a new search are stages of their own). False when
// the mission ended meanwhile.
bool follow(const EventLog& events, double seconds, double& following) {
  const auto start = WallClock::now();
  int samples = 0, followed = 0;
  while (seconds_since(start) < seconds) {
    if (!events.ended().empty()) return false;
    ++samples;
    if (events.stage() == "3 face-follow") ++followed;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  following = samples > 0 ? static_cast<double>(followed) / samples : 0.0;
  return true;
}

// Asks until the flight software accepts (it refuses a take-off before the link is up).
CommandVerdict request_when_ready(FlightService& flight, const MissionCommand& command, double timeout_s) {
  CommandVerdict v;
  wait_for([&] { return (v = flight.request(command)).accepted; }, timeout_s);
  return v;
}

// One mission on a running server, from the request until the drone is down.
RealtimeRun fly_mission(const RealtimeCampaignOptions& o, FlightService& flight, EventLog& events,
                        const fusion::LabGeometry& lab, const MissionCommand& command) {
  RealtimeRun run;
  run.instrument = command.instrument;
  events.next_mission();
  const auto start = WallClock::now();
  const CommandVerdict verdict = request_when_ready(flight, command, 15.0);
  if (!verdict.accepted) {
    run.result = "refused: " + verdict.reason;
  } else if (o.mission == RealtimeMission::Inspect) {
    const bool ended = wait_for([&] { return !events.ended().empty(); }, o.timeout_s);
    run.result = ended ? events.ended() : "timed out in stage '" + events.stage() + "'";
    run.landed = wait_for([&] { return !flight.telemetry().flying; }, 10.0);
    if (const auto truth = flight.telemetry().ground_truth)
      run.landing_error_m = std::hypot(truth->x_m - lab.base.x(), truth->y_m - lab.base.y());
    run.success = ended && run.result.find("ended: succeeded") != std::string::npos && run.landed &&
                  run.landing_error_m >= 0 && run.landing_error_m <= 0.10;
  } else {
    const bool found = wait_for([&] { return events.stage() == "3 face-follow"; }, o.timeout_s);
    const bool kept = found && follow(events, o.follow_s, run.following);
    run.result = !found ? "the teacher was not found (stage '" + events.stage() + "')"
                 : !kept ? events.ended()
                         : "followed the teacher " + std::to_string(std::lround(100 * run.following)) + " % of " +
                               std::to_string(static_cast<int>(o.follow_s)) + " s";
    request_when_ready(flight, {MissionCommandKind::Land, "", 0}, 5.0);
    run.landed = wait_for([&] { return !flight.telemetry().flying; }, 20.0);
    run.success = found && kept && run.following >= o.min_following && run.landed;
  }
  run.duration_s = seconds_since(start);
  run.timing = flight.timing();
  return run;
}

MissionCommand command_for(const RealtimeCampaignOptions& o, const fusion::LabGeometry& lab, int round) {
  MissionCommand command;
  if (o.mission == RealtimeMission::Inspect) {
    command.kind = MissionCommandKind::Inspect;
    const auto turn = static_cast<std::size_t>(round) % lab.instruments.size();
    command.instrument = o.instrument.empty() ? lab.instruments[turn].id : o.instrument;
    command.hold_s = o.hold_s;
  } else {
    command.kind = MissionCommandKind::FindTeacher;
  }
  return command;
}

// One server on the simulated lab of `seed`, flying `in_a_row` missions.
void fly_run(const RealtimeCampaignOptions& o, const AppConfig& base, unsigned seed, MissionTrace& trace,
             std::vector<RealtimeRun>& runs) {
  AppConfig config = base;
  config.sim.lab.seed = seed;
  config.sim.link.seed = seed;
  auto backend = make_drone_backend(DroneSpec{}, config, Logger("realtime", LogLevel::Off));
  FlightService& flight = backend->flight();
  EventLog events(trace);
  flight.set_sink(&events);
  const fusion::LabGeometry lab = fusion::lab_geometry_from(config.lab);
  std::atomic<bool> sampling{true};
  std::jthread sampler([&] {
    while (sampling) {
      trace.sample(flight.telemetry());
      std::this_thread::sleep_for(std::chrono::milliseconds(200));
    }
  });
  for (int round = 0; round < o.in_a_row; ++round) {
    trace.set_run(seed, round);
    RealtimeRun run = fly_mission(o, flight, events, lab, command_for(o, lab, round));
    run.seed = seed;
    run.round = round;
    runs.push_back(std::move(run));
  }
  sampling = false;
  sampler.join();
  flight.set_sink(nullptr);
  flight.land_and_stop(5.0);
}

}  // namespace

std::vector<RealtimeRun> run_realtime_campaign(const RealtimeCampaignOptions& o) {
  const AppConfig config = load_app_config(o.config_file);
  MissionTrace trace(o.trace_file);
  std::vector<RealtimeRun> runs;
  for (int i = 0; i < o.runs; ++i) fly_run(o, config, o.seed + static_cast<unsigned>(i), trace, runs);
  return runs;
}

}  // namespace labo::bench
