#pragma once
// Sessions valid across several labs (docs/web.md "Several labs"): every LaboDrone process of a
// front reads the same secret key, and a login at any of them issues a token the others verify
// without asking anyone: "s1.<user, hex>.<role>.<expiry, Unix s>.<nonce>.<HMAC-SHA256-128 of the rest>".
// The token carries no password and expires; a lab still refuses it when its own user list no longer
// has that user with that role. Thread-safe (const).
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "server/server_settings.hpp"

namespace labo::server {

struct SessionClaims {
  std::string user;
  Role role = Role::Student;
  double expires_unix_s = 0;
};

class SessionSigner {
 public:
  static constexpr std::size_t kMinKeyBytes = 32;
  static constexpr unsigned int kMacBytes = 16;  // HMAC-SHA256 truncated to 128 bits: tokens stay short
  // Throws std::runtime_error naming the file when it cannot be read or holds fewer than kMinKeyBytes.
  static SessionSigner from_key_file(const std::filesystem::path& file);
  explicit SessionSigner(std::vector<unsigned char> key);

  std::string issue(const std::string& user, Role role, double expires_unix_s) const;
  // The claims of a well-formed, correctly signed token that has not expired at `now_unix_s`.
  std::optional<SessionClaims> verify(const std::string& token, double now_unix_s) const;

 private:
  std::string mac_hex(const std::string& text) const;
  std::vector<unsigned char> key_;
};

}  // namespace labo::server
