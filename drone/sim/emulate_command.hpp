#pragma once
// `labodrone emulate`: the simulated lab as an AR.Drone 2.0 on UDP 5556/5554 and TCP 5555 (the
// ports of the config's "emulator" section), in real time, until Ctrl-C. Any AR.Drone 2.0 client
// (LaboDrone's own `serve --drone ardrone:127.0.0.1`, node-ar-drone, ardrone_autonomy) can fly it.
#include "core/cli_args.hpp"

namespace labo {

const CommandSpec& emulate_command_spec();
int run_emulate_command(const ParsedArgs& args);

}  // namespace labo
