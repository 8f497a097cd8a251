#pragma once
// `labodrone sim estimate --seed S [--runs N] [--plant lab|surrogate] [--vision truth|real] [--json]
// [--fit-model]`: the state-estimation experiments in lockstep (estimation_experiment.hpp), with the
// issue's targets beside each figure.
#include <filesystem>
#include <functional>

#include "core/cli_args.hpp"
#include "localization/estimation/eval/estimation_pipeline.hpp"

namespace labo {

// The real vision front-ends live in control/, above localization/: the app layer hands in a maker of
// their pipeline kind for a configuration file (server/estimation_vision.hpp).
using RealVisionMaker = std::function<PipelineKind(const std::filesystem::path& config_file)>;

const CommandSpec& sim_estimate_command_spec();
int run_sim_estimate_command(const ParsedArgs& args, const RealVisionMaker& real_vision);

}  // namespace labo
