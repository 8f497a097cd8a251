#pragma once
// Salted, iterated password hashes: PBKDF2-HMAC-SHA256 (OpenSSL), stored as
// "pbkdf2-sha256$<iterations>$<salt base64>$<hash base64>". Verification compares in constant time.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace labo::server {

struct PasswordHash {
  int iterations = 0;
  std::vector<std::uint8_t> salt;
  std::vector<std::uint8_t> hash;

  static constexpr int kDefaultIterations = 120000;
  static constexpr int kMinIterations = 10000;

  // A new hash with a random 16-byte salt.
  static PasswordHash create(const std::string& password, int iterations = kDefaultIterations);
  // nullopt when the text is not a well-formed hash.
  static std::optional<PasswordHash> parse(const std::string& encoded);
  std::string encode() const;
  bool verify(const std::string& password) const;
};

std::string base64_encode(const std::vector<std::uint8_t>& bytes);
std::optional<std::vector<std::uint8_t>> base64_decode(const std::string& text);
// n random bytes from OpenSSL's CSPRNG, as lowercase hex (session tokens).
std::string random_hex(std::size_t n_bytes);
// SHA-256 of the text as lowercase hex: sessions are kept on disk by their token's hash only.
std::string sha256_hex(const std::string& text);

}  // namespace labo::server
