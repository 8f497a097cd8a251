#pragma once
// The flight software of `labodrone serve` (FlightStackCore in a FlightRuntime, built as the drone
// backends build it) behind a FlightService the web server keeps while the soak restarts what is
// behind it. After a crash the flight software's pose is wherever the tumble left it, and it never
// re-anchors on its own: the soak then does what the lab would, puts the drone back on its platform
// and restarts the flight software (as a restart of `serve` would), so the rounds after a crash
// still test something. Every call waits while a restart is under way.
#include <memory>
#include <shared_mutex>

#include "core/log.hpp"
#include "core/time.hpp"
#include "server/app_config.hpp"
#include "server/runtime/flight_runtime.hpp"
#include "server/runtime/flight_stack_core.hpp"

namespace labo::bench {

using server::AppConfig;
using server::CommandVerdict;
using server::FlightEventSink;
using server::FlightRuntime;
using server::FlightService;
using server::FlightStackCore;
using server::FlightTelemetry;
using server::InstrumentSummary;
using server::MissionCommand;
using server::RuntimeTimingSummary;


class RestartableFlight final : public FlightService {
 public:
  RestartableFlight(DroneLink& link, const Clock& clock, const AppConfig& config, FlightStackCore::TruthSource truth,
                    Logger log);
  ~RestartableFlight() override;

  // Stops the runtime (without landing: the drone is down) and starts a new flight software.
  void restart();
  int restarts() const { return restarts_; }

  void set_sink(FlightEventSink* sink) override;
  CommandVerdict request(const MissionCommand& command) override;
  FlightTelemetry telemetry() const override;
  std::vector<InstrumentSummary> instruments() const override;
  CommandVerdict set_down_on_platform() override;
  void land_and_stop(double timeout_s) override;
  RuntimeTimingSummary timing() const override;

 private:
  void build();

  DroneLink& link_;
  const Clock& clock_;
  AppConfig config_;
  FlightStackCore::TruthSource truth_;
  Logger log_;
  mutable std::shared_mutex mutex_;
  FlightEventSink* sink_ = nullptr;
  std::unique_ptr<FlightStackCore> core_;
  std::unique_ptr<FlightRuntime> runtime_;  // destroyed before core_
  int restarts_ = 0;
};

}  // namespace labo::bench
