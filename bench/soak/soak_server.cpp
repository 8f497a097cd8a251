#include "bench/soak/soak_server.hpp"

#include "server/runtime/backend_parts.hpp"

namespace labo::bench {

using ardrone2::ArdroneLinkSettings;

using server::AppConfig;
using server::ServerSettings;
using server::loopback_link_settings;


namespace {
ServerSettings loopback_server(const AppConfig& config) {
  ServerSettings s = config.server;
  s.bind_address = "127.0.0.1";
  s.port = 0;  // a free port: the soak and the test suite run beside other servers
  return s;
}
ArdroneLinkSettings recorded_link(const AppConfig& config, const WifiRelay& relay, const std::filesystem::path& recording) {
  ArdroneLinkSettings s = loopback_link_settings(config, relay.at_port(), relay.navdata_port(), relay.video_port());
  s.recording = recording;
  return s;
}
}  // namespace

SoakServer::SoakServer(const AppConfig& config, const std::filesystem::path& config_file,
                       const std::filesystem::path& recording, Logger log)
    : drone_(config, log.child("drone")),
      relay_(drone_.at_port(), drone_.navdata_port(), drone_.video_port()),
      link_(recorded_link(config, relay_, recording), log.child("link")),
      flight_(link_, clock_, config, [this]() -> std::optional<Eigen::Isometry3d> { return drone_.T_world_body(); },
              log.child("runtime")),
      web_(loopback_server(config), config_file, flight_, log.child("web")) {
  link_.start();
  port_ = web_.start();
}

SoakServer::~SoakServer() { shutdown(0); }

void SoakServer::shutdown(double land_timeout_s) {
  if (stopped_) return;
  stopped_ = true;
  web_.shutdown(land_timeout_s);
  flight_.land_and_stop(0);
  link_.stop();
  drone_.stop();
}

}  // namespace labo::bench
