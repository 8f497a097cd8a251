#pragma once
// LabPipelines with the real vision front-ends: a PlanarFrontEnd per instrument with a template
// (front camera) and for the landing platform (bottom camera), the SLAM front-end on the front
// camera, and the face front-end for the teacher. Used by FlightStack when its setup asks for real
// vision (the server, and `labodrone-bench sim ... --vision real`).
#include <memory>

#include "core/camera_config.hpp"
#include "localization/fusion/front_end_settings.hpp"
#include "localization/fusion/lab_pipelines.hpp"

namespace labo::fusion {

// Throws std::invalid_argument (a template that cannot be used, naming the target) or
// std::runtime_error (a face model file that cannot be read, naming it).
std::unique_ptr<LabPipelines> make_lab_pipelines(const LabGeometry& lab, const CamerasConfig& cameras, const VisionThresholds& vision,
                                                 const estimation::EstimatorConfig& estimation, const FrontEndSettings& settings);

}  // namespace labo::fusion
