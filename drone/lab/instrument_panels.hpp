#pragma once
// Procedural front panels of the lab's instruments and the landing platform's pattern. Drawn with
// OpenCV primitives from fixed seeds, so `labodrone sim textures` regenerates the committed PNGs
// under config/instruments/ bit for bit. Panels carry what the homography tracker needs: displays
// with waveforms and digits, knobs, buttons, labels, asymmetric layouts (no 180-degree symmetry).
#include <filesystem>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace labo::lab {

cv::Mat draw_oscilloscope_panel();        // 800 x 400 (0.40 x 0.20 m)
cv::Mat draw_signal_generator_panel();    // 720 x 240 (0.36 x 0.12 m)
cv::Mat draw_power_supply_panel();        // 600 x 400 (0.24 x 0.16 m)
cv::Mat draw_landing_pattern();           // 600 x 600 (0.60 x 0.60 m)

// Writes every template as <dir>/<name>.png; returns the paths written.
std::vector<std::filesystem::path> write_instrument_templates(const std::filesystem::path& dir);

}  // namespace labo::lab
