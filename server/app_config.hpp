#pragma once
// The whole configuration of a LaboDrone process, read and validated from config/default.json (or
// --config FILE). Each section is read by the module that owns it.
#include <filesystem>
#include <string>

#include "control/control_config.hpp"
#include "core/camera_config.hpp"
#include "core/log.hpp"
#include "localization/estimation/estimation_config.hpp"
#include "localization/vision_thresholds.hpp"

namespace labo {

struct ServerSettings {
  std::string bind_address = "127.0.0.1";
  int port = 8080;
  std::filesystem::path web_root;  // resolved against the config file's folder
};

struct AppConfig {
  std::filesystem::path source;
  LogLevel log_level = LogLevel::Info;
  CamerasConfig cameras;
  VisionThresholds vision;
  ControlConfig control;
  EstimatorConfig estimation;
  ServerSettings server;
  std::filesystem::path lab_file;  // the simulated lab's description
};

// Throws ConfigError naming the file, the key path, the value and what was expected.
AppConfig load_app_config(const std::filesystem::path& file);
AppConfig read_app_config(const ConfigReader& root, const std::filesystem::path& base_dir);

// config/default.json of the source tree.
std::filesystem::path default_config_path();

}  // namespace labo
