#pragma once
// The "slam" section of the configuration: the tunable subset of SlamSettings. Every key is
// optional (defaults in SlamSettings); values are range-checked and unknown keys refused.
#include "core/config_reader.hpp"
#include "localization/slam/slam_system.hpp"

namespace labo::slam {

// Keys: every key read_slam_settings accepts is listed, with its range, in slam_config.cpp and
// docs/slam.md; the rest of SlamSettings is fixed in code.
SlamSettings read_slam_settings(const ConfigReader& node);

}  // namespace labo::slam
