#pragma once
// `labodrone sim render`: both cameras' images at a given drone pose, as PNG files. docs/sim_rendering.md.
//
// The teacher's face is built from a photograph by localization/ (drone/ cannot call it): the caller
// passes the loader.
#include <Eigen/Geometry>

#include "core/camera_config.hpp"
#include "core/cli_args.hpp"
#include "drone/lab/lab_description.hpp"
#include "drone/sim/head_model.hpp"

namespace labo::sim {

const CommandSpec& sim_render_command_spec();
int run_sim_render_command(const ParsedArgs& args, const TeacherHeadLoader& load_head);

// The lab and cameras a render command draws: `--config FILE` (default config/default.json) and its
// lab, or `--lab FILE`. Throws ConfigError / LabError naming the file and what is wrong.
struct RenderSetup {
  lab::LabDescription lab;
  CamerasConfig cameras;
};
RenderSetup load_render_setup(const ParsedArgs& args);

// The teacher standing at (x, y) on the floor, facing yaw (rad), eyes at the lab's eye height.
Eigen::Isometry3d teacher_head_pose(const lab::LabDescription& lab, double x, double y, double yaw);

}  // namespace labo::sim
