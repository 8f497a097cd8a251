#include "server/hash_password_command.hpp"

#include <iostream>
#include <string>

#include "server/auth/password_hash.hpp"

namespace labo::server {

const CommandSpec& hash_password_command_spec() {
  static const CommandSpec spec{
      "hash-password", "",
      "Read a password on standard input and print its salted PBKDF2 hash for server.users in the config.",
      {{"--iterations", "N", "PBKDF2-HMAC-SHA256 iterations (default 120000, at least 10000)"}}, 0, 0};
  return spec;
}

int run_hash_password_command(const ParsedArgs& args) {
  const int iterations = args.integer_or("--iterations", PasswordHash::kDefaultIterations, PasswordHash::kMinIterations, 10000000);
  std::string password;
  if (!std::getline(std::cin, password) || password.empty()) throw UsageError("give the password on standard input (one line, not empty)");
  std::cout << PasswordHash::create(password, iterations).encode() << "\n";
  return 0;
}

}  // namespace labo::server
