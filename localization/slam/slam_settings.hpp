#pragma once
// SlamSettings checked, and turned into each module's settings (the constants the system does not
// expose are set here, named).
#include "localization/slam/feature/feature_extractor.hpp"
#include "localization/slam/initialize/map_initializer.hpp"
#include "localization/slam/module/frame_tracker.hpp"
#include "localization/slam/module/local_mapper.hpp"
#include "localization/slam/slam_system.hpp"

namespace labo::slam {

// Throws std::invalid_argument naming the field and its allowed range.
void validate_settings(const SlamSettings& s);

ExtractorSettings extractor_settings(const SlamSettings& s);
InitializerSettings initializer_settings(const SlamSettings& s);
TrackerSettings tracker_settings(const SlamSettings& s);
MapperSettings mapper_settings(const SlamSettings& s);

}  // namespace labo::slam
