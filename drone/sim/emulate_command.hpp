#pragma once
// `labodrone emulate`: the simulated lab as an AR.Drone 2.0 on UDP 5556/5554 and TCP 5555 (the
// ports of the config's "emulator" section), or with `--protocol tello` as a Tello in SDK 2.0 mode
// on UDP 8889 (the "tello.emulator" section; its lab renders the Tello's camera), in real time, until
// Ctrl-C. Any client of that drone (LaboDrone's own `serve --drone ardrone:127.0.0.1` or
// `--drone tello:127.0.0.1`, node-ar-drone, ardrone_autonomy, a Tello SDK program) can fly it.
// The teacher's face comes from the caller (`load_head`, localization/face/teacher_head.hpp).
#include "core/cli_args.hpp"
#include "drone/sim/head_model.hpp"

namespace labo::sim {

const CommandSpec& emulate_command_spec();
int run_emulate_command(const ParsedArgs& args, const TeacherHeadLoader& load_head);

}  // namespace labo::sim
