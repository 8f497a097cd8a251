#pragma once
// `labodrone tello-state FILE`: decode a capture of Tello state strings (one per line, as a client
// printing the UDP 8890 datagrams saves them) or a flight recording (its state records), with the
// link's own parser. One JSON object per string: its fields in the drone's units and signs, and the
// navdata sample LaboDrone makes of it (SI units, LaboDrone's signs); a refused string gets "error"
// (the counter's kind) and "detail" instead. Exit 0 when at least one string was valid, 2 with a
// one-line reason on stderr otherwise (unreadable file, larger than 64 MiB, no valid state string).
#include "core/cli_args.hpp"

namespace labo::tello {

const CommandSpec& tello_state_command_spec();
int run_tello_state_command(const ParsedArgs& args);

}  // namespace labo::tello
