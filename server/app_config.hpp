#pragma once
// The whole configuration of a LaboDrone process, read and validated from config/default.json (or
// --config FILE). Each section is read by the module that owns it.
#include <filesystem>
#include <string>

#include "control/control_config.hpp"
#include "core/camera_config.hpp"
#include "core/log.hpp"
#include "localization/estimation/estimation_config.hpp"
#include "localization/face/face_config.hpp"
#include "drone/ardrone2/ardrone_emulator.hpp"
#include "drone/ardrone2/ardrone_link.hpp"
#include "drone/lab/lab_description.hpp"
#include "drone/sim/sim_config.hpp"
#include "drone/tello/tello_config.hpp"
#include "localization/planar/planar_config.hpp"
#include "localization/slam/slam_system.hpp"
#include "localization/vision_thresholds.hpp"
#include "server/server_settings.hpp"

namespace labo::server {

using sim::SimConfig;


struct AppConfig {
  std::filesystem::path source;
  LogLevel log_level = LogLevel::Info;
  CamerasConfig cameras;
  VisionThresholds vision;
  estimation::EstimatorConfig estimation;
  // What a Tello flies with: the tello section's "estimation" read over the estimation section.
  estimation::EstimatorConfig tello_estimation;
  control::ControlConfig control;
  planar::PlanarConfig planar;
  slam::SlamSettings slam;
  ServerSettings server;
  ardrone2::ArdroneLinkSettings link;          // the AR.Drone 2.0 driver (docs/ardrone2.md)
  ardrone2::ArdroneEmulatorSettings emulator;  // the AR.Drone 2.0 protocol emulator on loopback
  tello::TelloConfig tello;                    // the Tello link, its emulator and camera (docs/tello.md)
  std::filesystem::path lab_file;              // "lab": the lab description, relative to the config file
  lab::LabDescription lab;                     // loaded from lab_file and validated (docs/sim.md)
  SimConfig sim;                               // the simulated lab's physics, sensors, link, disturbances (docs/sim.md)
  face::FaceConfig face;
};

// Throws ConfigError naming the file, the key path, the value and what was expected.
AppConfig load_app_config(const std::filesystem::path& file);
AppConfig read_app_config(const ConfigReader& root, const std::filesystem::path& base_dir);

// config/default.json of the source tree.
std::filesystem::path default_config_path();

}  // namespace labo::server
