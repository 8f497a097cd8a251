#pragma once
// The real vision front-ends as an EstimationPipeline, for `labodrone-bench sim estimate --vision real`:
// fusion::LabPipelines (the StateEstimator and the handling of the front-ends' results, as the
// flight software runs them) with the SLAM front-end on the front camera and the planar front-end on
// the experiment's instrument, focused as each experiment phase asks (SLAM while hovering, the
// instrument's homography while servoing, nothing in dead reckoning).
#include <filesystem>

#include "bench/estimation/estimation_pipeline.hpp"

namespace labo::bench {

// The configuration's lab, cameras, "vision", "planar" and "slam" sections (SLAM in synchronous
// mapping, so a seed gives the same flight every time). Throws ConfigError naming the file and key.
PipelineKind real_vision_pipelines(const std::filesystem::path& config_file);

}  // namespace labo::bench
