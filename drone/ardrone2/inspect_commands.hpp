#pragma once
// `labodrone navdata FILE` and `labodrone video FILE [--frames DIR] [--protocol ardrone|tello]`: look
// inside a raw capture or a flight recording with the driver's own parsers (a Tello's video with the
// Tello link's, drone/tello/). Exit 0 on success, 2 on unreadable or invalid input with a one-line
// reason on stderr.
#include <string>

#include "core/cli_args.hpp"
#include "drone/ardrone2/navdata_packet.hpp"

namespace labo {

const CommandSpec& navdata_command_spec();
int run_navdata_command(const ParsedArgs& args);

const CommandSpec& video_command_spec();
int run_video_command(const ParsedArgs& args);

// One packet as a single-line JSON object: sequence, state flags by name, checksum_ok, and every
// option (snake_case keys, unit in the name, in the drone's own sign conventions) with its raw values.
std::string navdata_packet_json(const ardrone2::NavdataPacket& packet);

}  // namespace labo
