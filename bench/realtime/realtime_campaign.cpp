#include "bench/realtime/realtime_campaign.hpp"

#include <chrono>
#include <cmath>
#include <mutex>
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

// The mission's log lines and stage changes, as the web server would receive them.
class EventLog final : public FlightEventSink {
 public:
  void on_frame(const WireFrame&) override {}
  void on_flight_event(const FlightEvent& e) override {
    std::lock_guard lock(mutex_);
    if (e.kind == "stage") stage_ = e.stage;
    if (e.kind == "log" && e.message.find("' ended: ") != std::string::npos) ended_ = e.message;
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

RealtimeRun fly_one(const RealtimeCampaignOptions& o, const AppConfig& base, unsigned seed) {
  AppConfig config = base;
  config.sim.lab.seed = seed;
  config.sim.link.seed = seed;
  RealtimeRun run;
  run.seed = seed;
  auto backend = make_drone_backend(DroneSpec{}, config, Logger("realtime", LogLevel::Off));
  FlightService& flight = backend->flight();
  EventLog events;
  flight.set_sink(&events);
  const fusion::LabGeometry lab = fusion::lab_geometry_from(config.lab);
  MissionCommand command;
  if (o.mission == RealtimeMission::Inspect) {
    command.kind = MissionCommandKind::Inspect;
    command.instrument = o.instrument.empty() ? lab.instruments.front().id : o.instrument;
    command.hold_s = o.hold_s;
  } else {
    command.kind = MissionCommandKind::FindTeacher;
  }
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
  flight.set_sink(nullptr);
  flight.land_and_stop(5.0);
  return run;
}

}  // namespace

std::vector<RealtimeRun> run_realtime_campaign(const RealtimeCampaignOptions& o) {
  const AppConfig config = load_app_config(o.config_file);
  std::vector<RealtimeRun> runs;
  for (int i = 0; i < o.runs; ++i) runs.push_back(fly_one(o, config, o.seed + static_cast<unsigned>(i)));
  return runs;
}

}  // namespace labo::bench
