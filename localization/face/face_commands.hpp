#pragma once
// `labodrone face register`: fit a person's CANDIDE-3 shape from frontal pictures and store it.
#include "core/camera_config.hpp"
#include "core/camera_model.hpp"
#include "core/cli_args.hpp"
#include "localization/face/face_config.hpp"

namespace labo {

// The configuration's "face" section and front camera (`--config FILE`, default
// config/default.json; built-in defaults for a missing section). Throws ConfigError naming the key.
struct FaceSetup {
  face::FaceConfig face;
  PinholeCamera camera;
  CamerasConfig cameras;
};
FaceSetup load_face_setup(const ParsedArgs& args);

const CommandSpec& face_register_command_spec();
int run_face_register_command(const ParsedArgs& args);

}  // namespace labo
