#pragma once
// `labodrone homography TEMPLATE IMAGE [--method auto|template|sift]` (exit 0 found, 3 not found,
// 2 bad input), and the planar settings it shares with `labodrone-bench bench planar`.
#include "core/cli_args.hpp"
#include "localization/planar/planar_config.hpp"
#include "localization/vision_thresholds.hpp"

namespace labo::planar {

// The "vision" and "planar" sections of `--config FILE` (built-in defaults without it).
struct PlanarCommandSettings {
  VisionThresholds vision;
  PlanarConfig planar;
};
PlanarCommandSettings read_planar_command_settings(const ParsedArgs& args);

const CommandSpec& homography_command_spec();
int run_homography_command(const ParsedArgs& args);

}  // namespace labo::planar
