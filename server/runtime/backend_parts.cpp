#include "server/runtime/backend_parts.hpp"

#include "drone/sim/sim_setup.hpp"
#include "localization/face/teacher_head.hpp"
#include "localization/fusion/lab_geometry.hpp"
#include "server/runtime/lab_outline.hpp"

namespace labo::server {

using ardrone2::ArdroneEmulatorSettings;
using ardrone2::ArdroneLink;
using ardrone2::ArdroneLinkSettings;

using sim::SimulatedLab;
using sim::make_sim_world;
using sim::make_simulated_lab;


control::FlightStackSetup flight_stack_setup(const AppConfig& config) {
  // The lab's geometry (room, base, instruments, platform) from the lab description the config
  // names (validated when the config was loaded).
  control::FlightStackSetup setup;
  setup.lab = fusion::lab_geometry_from(config.lab);
  setup.control = config.control;
  setup.cameras = config.cameras;
  setup.vision = config.vision;
  setup.estimation = config.estimation;
  // The real vision pipelines on the drone's frames (localization/fusion/lab_pipelines_factory.hpp).
  setup.front_ends = fusion::FrontEndSettings{config.planar, config.slam, config.face, true};
  return setup;
}

control::FlightStackSetup flight_stack_setup(const AppConfig& config, const CamerasConfig& cameras,
                                             const estimation::EstimatorConfig& estimation) {
  control::FlightStackSetup setup = flight_stack_setup(config);
  setup.cameras = cameras;
  setup.estimation = estimation;
  return setup;
}

FlightRuntimeOptions flight_runtime_options(const AppConfig& config) {
  FlightRuntimeOptions o;
  o.jpeg_quality = config.server.video.jpeg_quality;
  o.low_rendition.bitrate_kbps = config.server.video.low_rendition_kbps;
  o.front_camera = PinholeCamera(config.cameras.front);
  o.lab_outline = lab_outline_from(config.lab);
  return o;
}

FlightRuntimeOptions flight_runtime_options(const AppConfig& config, ArdroneLink& link) {
  FlightRuntimeOptions o = flight_runtime_options(config);
  o.video = {"AR.Drone 2.0", true, "", true, link.video_bitrate_kbps(), ardrone2::kMinVideoBitrateKbps, ardrone2::kMaxVideoBitrateKbps};
  o.set_video_bitrate = [&link](int kbps) { link.set_video_bitrate_kbps(kbps); };
  return o;
}

FlightRuntimeOptions flight_runtime_options(const AppConfig& config, const std::string& drone, const std::string& no_bottom_camera) {
  FlightRuntimeOptions o = flight_runtime_options(config);
  o.video = {drone, false, no_bottom_camera, false, 0, 0, 0};
  return o;
}

// The world is the config's `sim.world`: the flight runtime is built from the config alone, and a
// randomized world's delays are the loopback's, not drawn ones.
std::unique_ptr<SimulatedLab> make_configured_lab(const AppConfig& config) {
  return make_simulated_lab(make_sim_world(config.lab, config.cameras, config.sim),
                            face::load_lab_teacher_head(config.lab, config.face));
}

ArdroneEmulatorSettings loopback_emulator_settings(const AppConfig& config) {
  ArdroneEmulatorSettings s = config.emulator;
  s.bind_host = "127.0.0.1";
  s.at_port = s.navdata_port = s.video_port = 0;
  return s;
}

ArdroneLinkSettings loopback_link_settings(const AppConfig& config, int at_port, int navdata_port, int video_port) {
  ArdroneLinkSettings s = config.link;
  s.host = "127.0.0.1";
  s.at_port = at_port;
  s.navdata_port = navdata_port;
  s.video_port = video_port;
  return s;
}

}  // namespace labo::server
