#pragma once
// What the real vision front-ends are built from (make_lab_pipelines()): each pipeline's own config
// section. The paper's thresholds (alpha, beta, D, lambda, N) are FlightStackSetup::vision, the
// cameras FlightStackSetup::cameras.
#include <filesystem>

#include "core/config_reader.hpp"
#include "localization/face/face_config.hpp"
#include "localization/planar/planar_config.hpp"
#include "localization/slam/slam_system.hpp"

namespace labo::fusion {

struct FrontEndSettings {
  planar::PlanarConfig planar;
  slam::SlamSettings slam;
  face::FaceConfig face = face::default_face_config();
  // The face front-end loads dlib's landmark model (about 100 MB); runs that never look for the
  // teacher may go without it.
  bool with_face = true;
};

// The "planar", "slam" and "face" sections of a whole configuration (each optional: defaults), paths
// relative to `base_dir`. Other sections are left to their readers.
FrontEndSettings read_front_end_settings(const ConfigReader& root, const std::filesystem::path& base_dir);

}  // namespace labo::fusion
