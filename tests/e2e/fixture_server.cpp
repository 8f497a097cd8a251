// The browser test's and the web benchmark's server: the real WebServer and FlightRuntime, with the
// drone and the flight software replaced by the test doubles of tests/server/support (a 30 fps test
// card, also H.264-encoded as the drone sends it, and a scripted inspection). It exercises everything of the web layer without the simulated
// lab. Usage: labo_e2e_server PORT [STAGE_SECONDS] [FPS] [textured|plain] [CONFIG_FILE]
#include <iostream>
#include <string>

#include "server/app_config.hpp"
#include "server/http/web_server.hpp"
#include "server/runtime/flight_runtime.hpp"
#include "server/runtime/lab_outline.hpp"
#include "tests/server/support/fake_drone.hpp"

int main(int argc, char** argv) {
  using namespace labo;
  using namespace labo::server;
  if (argc < 2) {
    std::cerr << "usage: labo_e2e_server PORT [STAGE_SECONDS] [FPS] [textured|plain] [CONFIG_FILE]\n";
    return 2;
  }
  try {
    const std::filesystem::path config_file = argc > 5 ? std::filesystem::path(argv[5]) : default_config_path();
    AppConfig config = load_app_config(config_file);
    config.server.port = std::stoi(argv[1]);
    const double stage_s = argc > 2 ? std::stod(argv[2]) : 2.0;
    const double fps = argc > 3 ? std::stod(argv[3]) : 30.0;
    Logger log("e2e", LogLevel::Warn);
    SteadyClock clock;
    test::FakeDroneLink link;
    test::ScriptedCore core(stage_s);
    FlightRuntimeOptions options;
    options.jpeg_quality = config.server.video.jpeg_quality;
    options.low_rendition.bitrate_kbps = config.server.video.low_rendition_kbps;
    // Like an AR.Drone 2.0: both cameras (the test card turns dark on the bottom one) and a bit rate
    // an admin may set (the test card's encoder keeps its own).
    options.video = {"AR.Drone 2.0 (test card)", true, "", true, 4000, 250, 4000};
    options.set_video_bitrate = [](int) {};
    options.lab_outline = lab_outline_from(config.lab);
    FlightRuntime runtime(link, core, clock, options, log.child("runtime"));
    WebServer server(config.server, config_file, runtime, log.child("web"));
    runtime.start();
    const unsigned short port = server.start();
    link.set_textured(argc > 4 && std::string(argv[4]) == "textured");
    link.set_h264(true);
    link.start_pump(clock, fps);
    std::cout << "listening " << port << std::endl;
    server.run_until_signal();
    link.stop_pump();
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "labo_e2e_server: " << e.what() << "\n";
    return 1;
  }
}
