#pragma once
// `labodrone-bench bench vision --part detectors`: the planar detectors side by side on the same
// rendered views of the lab's oscilloscope in the front camera. Far (2.1-3.9 m, beyond lambda):
// template matching's two searches; near (0.5-1.9 m, rolled up to +-20 deg): the paper's SIFT, SIFT
// on the halved frame, ORB, BRISK, AKAZE. Every frame is a detection (the front-end is reset before
// it) with the distance the estimator would predict (the true one off by up to 8 %, deterministic),
// timed as flight runs it: the whole step (detection, the tracker's refinement, the pose). The first
// frame after construction is reported apart: the target is that no frame, that one included,
// exceeds the 33 ms frame period.
#include <string>
#include <vector>

#include "bench/frame_timing.hpp"
#include "core/camera_model.hpp"
#include "localization/fusion/lab_geometry.hpp"
#include "localization/planar/planar_config.hpp"
#include "localization/vision_thresholds.hpp"

namespace labo::bench {

struct DetectorRow {
  std::string range;    // "far" or "near"
  std::string name;     // e.g. "template coarse_to_fine", "orb"
  std::string config;   // the "planar" keys that select it
  bool is_default = false;  // what the configuration given to the bench runs
  int frames = 0, found = 0;
  double load_ms = 0;   // the front-end's construction: template features, precomputed templates, warm-up
  FrameTimes times;     // per frame, the first one included
};

std::vector<DetectorRow> compare_detectors(const fusion::PlanarTarget& target, const PinholeCamera& camera,
                                           const VisionThresholds& vision, const planar::PlanarConfig& config, int frames);

}  // namespace labo::bench
