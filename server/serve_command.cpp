#include "server/serve_command.hpp"

#include <iostream>

#include "server/app_config.hpp"
#include "server/http/web_server.hpp"
#include "server/runtime/drone_backend.hpp"

namespace labo {

const CommandSpec& serve_command_spec() {
  static const CommandSpec spec{
      "serve",
      "",
      "Start the LaboDrone server: the web UI and API on one port, flying the simulated lab by default.",
      {{"--config", "FILE", "configuration file (default: config/default.json)"},
       {"--port", "N", "TCP port to listen on (default: from the config, 8080)"},
       {"--bind", "ADDR", "address to listen on (default: from the config, 127.0.0.1)"},
       {"--drone", "SPEC", "sim (default: the simulated lab on loopback), ardrone[:HOST], tello[:HOST] or replay:FILE"}},
      0,
      0};
  return spec;
}

int run_serve_command(const ParsedArgs& args) {
  const std::filesystem::path config_file = args.value_or("--config", default_config_path().string());
  AppConfig config = load_app_config(config_file);
  config.server.bind_address = args.value_or("--bind", config.server.bind_address);
  config.server.port = args.integer_or("--port", config.server.port, 1, 65535);
  const DroneSpec drone = parse_drone_spec(args.value_or("--drone", "sim"));  // UsageError when malformed
  Logger log("labodrone", config.log_level);
  auto backend = make_drone_backend(drone, config, log.child("runtime"));
  WebServer server(config.server, config_file, backend->flight(), log.child("web"));
  server.start();
  std::cout << "LaboDrone is serving on " << (config.server.tls.enabled() ? "https://" : "http://") << config.server.bind_address << ":" << config.server.port
            << "/ (drone: " << describe(drone) << ")" << std::endl;
  server.run_until_signal();
  return 0;
}

}  // namespace labo
