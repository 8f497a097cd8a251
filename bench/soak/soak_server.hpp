#pragma once
// `labodrone serve --drone sim` assembled in-process from the same parts (server/runtime/
// backend_parts.hpp): the simulated lab under the emulator on loopback, the real driver, the flight
// software in FlightRuntime, the real WebServer on a free loopback port; with the soak's two fault
// points between them: the drone can be switched off and on (RestartableDrone) and the link cut
// (WifiRelay, between the emulator and the driver). The driver records the flight (link.recording).
#include <filesystem>
#include <memory>

#include "bench/soak/restartable_drone.hpp"
#include "bench/soak/restartable_flight.hpp"
#include "bench/soak/wifi_relay.hpp"
#include "drone/ardrone2/ardrone_link.hpp"
#include "server/http/web_server.hpp"

namespace labo::bench {

using server::AppConfig;
using server::FlightRuntime;
using server::FlightService;
using server::ServerMetrics;
using server::WebServer;


class SoakServer {
 public:
  // Starts everything; `recording` is the driver's recording file (empty: none).
  SoakServer(const AppConfig& config, const std::filesystem::path& config_file, const std::filesystem::path& recording,
             Logger log);
  ~SoakServer();

  unsigned short port() const { return port_; }
  RestartableDrone& drone() { return drone_; }
  WifiRelay& relay() { return relay_; }
  FlightService& flight() { return flight_; }
  // After a crash: the flight software restarted behind the web server (RestartableFlight).
  void restart_flight() { flight_.restart(); }
  int flight_restarts() const { return flight_.restarts(); }
  ServerMetrics& metrics() { return web_.metrics(); }
  LinkStatistics link_statistics() const { return link_.statistics(); }

  // As `serve` stops on SIGTERM: lands (the web server first, so clients see it), closes the
  // clients, stops the runtime, the driver (its recording flushed) and the drone. Idempotent.
  void shutdown(double land_timeout_s);
  // The recording's bytes the driver's writer reported (final after shutdown()).
  std::uint64_t recorded_bytes() const { return link_.recorded_bytes(); }

 private:
  RestartableDrone drone_;
  WifiRelay relay_;
  SteadyClock clock_;
  ardrone2::ArdroneLink link_;
  RestartableFlight flight_;
  WebServer web_;
  unsigned short port_ = 0;
  bool stopped_ = false;
};

}  // namespace labo::bench
