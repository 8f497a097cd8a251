#include "server/auth/session_signer.hpp"

#include <openssl/crypto.h>
#include <openssl/evp.h>
#include <openssl/hmac.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <iterator>
#include <stdexcept>

#include "server/auth/password_hash.hpp"

namespace labo::server {
namespace {

std::string to_hex(const unsigned char* bytes, std::size_t n) {
  static constexpr char digits[] = "0123456789abcdef";
  std::string out;
  out.reserve(2 * n);
  for (std::size_t i = 0; i < n; ++i) {
    out.push_back(digits[bytes[i] >> 4]);
    out.push_back(digits[bytes[i] & 15]);
  }
  return out;
}

std::optional<std::string> from_hex(const std::string& hex) {
  if (hex.size() % 2 != 0) return std::nullopt;
  std::string out;
  for (std::size_t i = 0; i < hex.size(); i += 2) {
    unsigned v = 0;
    const auto [end, err] = std::from_chars(hex.data() + i, hex.data() + i + 2, v, 16);
    if (err != std::errc{} || end != hex.data() + i + 2) return std::nullopt;
    out.push_back(static_cast<char>(v));
  }
  return out;
}

std::vector<std::string> split(const std::string& text, char sep) {
  std::vector<std::string> parts(1);
  for (const char c : text) {
    if (c == sep) parts.emplace_back();
    else parts.back().push_back(c);
  }
  return parts;
}

}  // namespace

SessionSigner SessionSigner::from_key_file(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw std::runtime_error("session key file " + file.string() + ": cannot be read");
  std::vector<unsigned char> key{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  while (!key.empty() && (key.back() == '\n' || key.back() == '\r')) key.pop_back();
  if (key.size() < kMinKeyBytes)
    throw std::runtime_error("session key file " + file.string() + ": " + std::to_string(key.size()) +
                             " bytes, expected at least " + std::to_string(kMinKeyBytes) +
                             " (e.g. head -c 48 /dev/urandom | base64 > FILE)");
  return SessionSigner(std::move(key));
}

SessionSigner::SessionSigner(std::vector<unsigned char> key) : key_(std::move(key)) {
  if (key_.size() < kMinKeyBytes) throw std::invalid_argument("session key shorter than 32 bytes");
}

std::string SessionSigner::mac_hex(const std::string& text) const {
  unsigned char mac[EVP_MAX_MD_SIZE];
  unsigned int n = 0;
  if (!HMAC(EVP_sha256(), key_.data(), static_cast<int>(key_.size()), reinterpret_cast<const unsigned char*>(text.data()),
            text.size(), mac, &n))
    throw std::runtime_error("HMAC-SHA256 failed in OpenSSL");
  return to_hex(mac, std::min<unsigned int>(n, kMacBytes));
}

std::string SessionSigner::issue(const std::string& user, Role role, double expires_unix_s) const {
  const std::string body = "s1." + to_hex(reinterpret_cast<const unsigned char*>(user.data()), user.size()) + "." +
                           to_string(role) + "." + std::to_string(static_cast<long long>(std::floor(expires_unix_s))) +
                           "." + random_hex(8);
  return body + "." + mac_hex(body);
}

std::optional<SessionClaims> SessionSigner::verify(const std::string& token, double now_unix_s) const {
  const std::vector<std::string> parts = split(token, '.');
  if (parts.size() != 6 || parts[0] != "s1") return std::nullopt;
  const std::string body = token.substr(0, token.rfind('.'));
  const std::string expected = mac_hex(body);
  if (parts[5].size() != expected.size() || CRYPTO_memcmp(parts[5].data(), expected.data(), expected.size()) != 0)
    return std::nullopt;
  const auto user = from_hex(parts[1]);
  long long expires = 0;
  const auto [end, err] = std::from_chars(parts[3].data(), parts[3].data() + parts[3].size(), expires);
  if (!user || user->empty() || err != std::errc{} || end != parts[3].data() + parts[3].size()) return std::nullopt;
  if (static_cast<double>(expires) <= now_unix_s) return std::nullopt;
  try {
    return SessionClaims{*user, parse_role(parts[2]), static_cast<double>(expires)};
  } catch (const std::invalid_argument&) {
    return std::nullopt;  // signed by us, so never; but a role name this build does not know is refused
  }
}

}  // namespace labo::server
