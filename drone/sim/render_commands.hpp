#pragma once
// `labodrone sim render`: both cameras' images at a given drone pose, as PNG files.
// `labodrone bench render`: the renderer's time per frame (median, p95) along a flight through the lab,
// for each camera, sharp and with motion blur and noise. docs/sim_rendering.md.
//
// The teacher's face is built from a photograph by localization/ (drone/ cannot call it): the caller
// passes the loader.
#include "core/cli_args.hpp"
#include "drone/lab/lab_description.hpp"
#include "drone/sim/head_model.hpp"

namespace labo {

const CommandSpec& sim_render_command_spec();
int run_sim_render_command(const ParsedArgs& args, const TeacherHeadLoader& load_head);

const CommandSpec& bench_render_command_spec();
int run_bench_render_command(const ParsedArgs& args, const TeacherHeadLoader& load_head);

}  // namespace labo
