#pragma once
#include <span>
#include <string>

#include "core/cli_args.hpp"

namespace labo::server {

const CommandSpec& serve_command_spec();
int run_serve_command(const ParsedArgs& args);

}  // namespace labo::server
