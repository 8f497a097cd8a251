#pragma once
// The "slam" section of the configuration: the tunable subset of SlamSettings. Every key is
// optional (defaults in SlamSettings); values are range-checked and unknown keys refused.
#include "core/config_reader.hpp"
#include "localization/slam/slam_system.hpp"

namespace labo::slam {

// Keys: mapping ("threaded" | "synchronous"), max_features, fast_threshold, quality_good,
// quality_lost, keyframe_min_interval_s, max_keyframes, global_ba_when_idle, global_ba_max_keyframes,
// global_ba_fixed_keyframes, global_ba_every (synchronous mode), local_ba_keyframes, cull_points,
// loop_closure, loop_min_gap_s.
SlamSettings read_slam_settings(const ConfigReader& node);

}  // namespace labo::slam
