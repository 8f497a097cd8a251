#include "server/serve_command.hpp"

#include "server/app_config.hpp"
#include "server/static_http_server.hpp"

namespace labo {

const CommandSpec& serve_command_spec() {
  static const CommandSpec spec{
      "serve",
      "",
      "Start the LaboDrone server: the web UI and API on one port, flying the simulated lab by default.",
      {{"--config", "FILE", "configuration file (default: config/default.json)"},
       {"--port", "N", "TCP port to listen on (default: from the config, 8080)"},
       {"--bind", "ADDR", "address to listen on (default: from the config, 127.0.0.1)"}},
      0,
      0};
  return spec;
}

int run_serve_command(const ParsedArgs& args) {
  const AppConfig config = load_app_config(args.value_or("--config", default_config_path().string()));
  StaticHttpServerOptions options;
  options.bind_address = args.value_or("--bind", config.server.bind_address);
  options.port = args.integer_or("--port", config.server.port, 1, 65535);
  options.web_root = config.server.web_root;
  return run_static_http_server(options);
}

}  // namespace labo
