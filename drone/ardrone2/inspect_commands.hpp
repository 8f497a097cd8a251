#pragma once
// `labodrone navdata FILE` and `labodrone video FILE [--frames DIR] [--protocol ardrone|tello]`: look
// inside a raw capture or a flight recording with the driver's own parsers (a Tello's video with the
// Tello link's, drone/tello/). Exit 0 on success, 2 on unreadable or invalid input with a one-line
// reason on stderr.
#include "core/cli_args.hpp"

namespace labo::ardrone2 {

const CommandSpec& navdata_command_spec();
int run_navdata_command(const ParsedArgs& args);

const CommandSpec& video_command_spec();
int run_video_command(const ParsedArgs& args);

}  // namespace labo::ardrone2
