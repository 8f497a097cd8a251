#include "bench/soak/restartable_flight.hpp"

#include <mutex>

#include "server/runtime/backend_parts.hpp"

namespace labo::bench {

using server::AppConfig;
using server::CommandVerdict;
using server::FlightEventSink;
using server::FlightRuntime;
using server::FlightStackCore;
using server::FlightTelemetry;
using server::InstrumentSummary;
using server::MissionCommand;
using server::RuntimeTimingSummary;
using server::flight_runtime_options;
using server::flight_stack_setup;


RestartableFlight::RestartableFlight(DroneLink& link, const Clock& clock, const AppConfig& config,
                                     FlightStackCore::TruthSource truth, Logger log)
    : link_(link), clock_(clock), config_(config), truth_(std::move(truth)), log_(std::move(log)) {
  build();
}

RestartableFlight::~RestartableFlight() {
  std::unique_lock lock(mutex_);
  runtime_.reset();
  core_.reset();
}

void RestartableFlight::build() {
  core_ = std::make_unique<FlightStackCore>(std::make_unique<control::FlightStack>(flight_stack_setup(config_)),
                                            config_.cameras);
  core_->set_truth_source(truth_);
  runtime_ = std::make_unique<FlightRuntime>(link_, *core_, clock_, flight_runtime_options(config_), log_);
  runtime_->set_sink(sink_);
  runtime_->start();
}

void RestartableFlight::restart() {
  // No more calls into the web layer first (the runtime calls its sink under its own lock, so none
  // is under way once this returns): joining the runtime's threads below cannot then wait for a web
  // thread that waits for this restart. Only the soak's script thread restarts.
  runtime_->set_sink(nullptr);
  std::unique_lock lock(mutex_);
  runtime_.reset();  // stops its threads and leaves the link
  core_.reset();
  build();
  ++restarts_;
}

void RestartableFlight::set_sink(FlightEventSink* sink) {
  std::unique_lock lock(mutex_);
  sink_ = sink;
  runtime_->set_sink(sink);
}

CommandVerdict RestartableFlight::request(const MissionCommand& command) {
  std::shared_lock lock(mutex_);
  return runtime_->request(command);
}

FlightTelemetry RestartableFlight::telemetry() const {
  std::shared_lock lock(mutex_);
  return runtime_->telemetry();
}

std::vector<InstrumentSummary> RestartableFlight::instruments() const {
  std::shared_lock lock(mutex_);
  return runtime_->instruments();
}

CommandVerdict RestartableFlight::set_down_on_platform() {
  std::shared_lock lock(mutex_);
  return runtime_->set_down_on_platform();
}

void RestartableFlight::land_and_stop(double timeout_s) {
  std::shared_lock lock(mutex_);
  runtime_->land_and_stop(timeout_s);
}

RuntimeTimingSummary RestartableFlight::timing() const {
  std::shared_lock lock(mutex_);
  return runtime_->timing();
}

}  // namespace labo::bench
