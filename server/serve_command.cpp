#include "server/serve_command.hpp"

#include <iostream>

#include "server/app_config.hpp"
#include "server/http/web_server.hpp"
#include "server/runtime/drone_backend.hpp"
#include "server/video/rtp_video_tap.hpp"
#include "server/http/heap_release.hpp"

namespace labo::server {

using tello::tello_cameras;


const CommandSpec& serve_command_spec() {
  static const CommandSpec spec{
      "serve",
      "",
      "Start the LaboDrone server: the web UI and API on one port, flying the simulated lab by default.",
      {{"--config", "FILE", "configuration file (default: config/default.json)"},
       {"--port", "N", "TCP port to listen on (default: from the config, 8080)"},
       {"--bind", "ADDR", "address to listen on (default: from the config, 127.0.0.1)"},
       {"--drone", "SPEC", "sim (default: the simulated lab on loopback), ardrone[:HOST], tello[:HOST] or replay:FILE"},
       {"--rtp-video", "HOST:PORT", "also forward the drone's H.264 as RTP to a media server (a Janus streaming mount point)"},
       {"--geometry-udp", "HOST:PORT", "with --rtp-video: also send each frame's overlay geometry as UDP datagrams to the mount point's data port"},
       {"--labs", "FILE", "the lab directory of a front of several labs, served at /api/labs (needs --lab-id)"},
       {"--lab-id", "ID", "this lab's id in the lab directory"},
       {"--session-key", "FILE", "a secret shared by the labs of a front (at least 32 bytes): sessions valid at all of them"}},
      0,
      0};
  return spec;
}

namespace {

// The UDP target of option `name` (HOST:PORT), if given; UsageError when malformed.
std::optional<UdpTarget> udp_target_option(const ParsedArgs& args, const std::string& name) {
  const auto text = args.value(name);
  if (!text) return std::nullopt;
  std::string error;
  auto target = parse_udp_target(*text, error);
  if (!target) throw UsageError(name + " " + error);
  return target;
}

}  // namespace

int run_serve_command(const ParsedArgs& args) {
  configure_server_heap();
  const std::filesystem::path config_file = args.value_or("--config", default_config_path().string());
  AppConfig config = load_app_config(config_file);
  config.server.bind_address = args.value_or("--bind", config.server.bind_address);
  config.server.port = args.integer_or("--port", config.server.port, 1, 65535);
  config.server.multi_lab.labs_file = args.value_or("--labs", "");
  config.server.multi_lab.lab_id = args.value_or("--lab-id", "");
  config.server.multi_lab.session_key_file = args.value_or("--session-key", "");
  if (config.server.multi_lab.labs_file.empty() != config.server.multi_lab.lab_id.empty())
    throw UsageError("--labs and --lab-id go together: the directory, and this lab's entry in it");
  const DroneSpec drone = parse_drone_spec(args.value_or("--drone", "sim"));  // UsageError when malformed
  // Faces are registered from photos taken with the front camera of the drone that flies.
  if (drone.kind == DroneSpec::Kind::Tello) config.server.people.front_camera = tello_cameras(config.tello, config.cameras).front;
  Logger log("labodrone", config.log_level);
  const std::optional<UdpTarget> rtp_target = udp_target_option(args, "--rtp-video");
  const std::optional<UdpTarget> geometry_target = udp_target_option(args, "--geometry-udp");
  if (geometry_target && !rtp_target) throw UsageError("--geometry-udp needs --rtp-video: the geometry goes with the video it overlays");
  auto backend = make_drone_backend(drone, config, log.child("runtime"));
  std::optional<RtpVideoForwarder> forwarder;
  std::optional<GeometryForwarder> geometry;
  std::optional<RtpVideoTap> tap;
  if (rtp_target) {
    forwarder.emplace(*rtp_target);
    if (geometry_target) geometry.emplace(*geometry_target);
    tap.emplace(backend->flight(), *forwarder, geometry ? &*geometry : nullptr);
  }
  WebServer server(config.server, config_file, tap ? static_cast<FlightService&>(*tap) : backend->flight(),
                   log.child("web"));
  server.start();
  std::cout << "LaboDrone is serving on " << (config.server.tls.enabled() ? "https://" : "http://") << config.server.bind_address << ":" << config.server.port
            << "/ (drone: " << describe(drone) << ")" << std::endl;
  if (rtp_target)
    std::cout << "H.264 forwarded as RTP to " << rtp_target->host << ":" << rtp_target->port << std::endl;
  if (geometry_target)
    std::cout << "overlay geometry sent as UDP to " << geometry_target->host << ":" << geometry_target->port << std::endl;
  server.run_until_signal();
  return 0;
}

}  // namespace labo::server
