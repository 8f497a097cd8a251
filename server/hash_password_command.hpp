#pragma once
#include "core/cli_args.hpp"

namespace labo::server {

// `labodrone hash-password`: reads a password on standard input, prints the PBKDF2 hash to put in
// server.users[].password_hash.
const CommandSpec& hash_password_command_spec();
int run_hash_password_command(const ParsedArgs& args);

}  // namespace labo::server
