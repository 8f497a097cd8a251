#include "server/auth/password_hash.hpp"

#include <openssl/crypto.h>
#include <openssl/evp.h>
#include <openssl/rand.h>

#include <stdexcept>

namespace labo::server {

namespace {

constexpr char kAlphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
constexpr const char* kScheme = "pbkdf2-sha256";

std::vector<std::uint8_t> derive(const std::string& password, const std::vector<std::uint8_t>& salt, int iterations,
                                 std::size_t length) {
  std::vector<std::uint8_t> out(length);
  if (PKCS5_PBKDF2_HMAC(password.data(), static_cast<int>(password.size()), salt.data(), static_cast<int>(salt.size()),
                        iterations, EVP_sha256(), static_cast<int>(out.size()), out.data()) != 1)
    throw std::runtime_error("PBKDF2 failed");
  return out;
}

std::vector<std::uint8_t> random_bytes(std::size_t n) {
  std::vector<std::uint8_t> bytes(n);
  if (RAND_bytes(bytes.data(), static_cast<int>(n)) != 1) throw std::runtime_error("no randomness from OpenSSL");
  return bytes;
}

}  // namespace

std::string base64_encode(const std::vector<std::uint8_t>& bytes) {
  std::string out;
  std::uint32_t acc = 0;
  int bits = 0;
  for (std::uint8_t b : bytes) {
    acc = (acc << 8) | b;
    bits += 8;
    while (bits >= 6) {
      bits -= 6;
      out.push_back(kAlphabet[(acc >> bits) & 63]);
    }
  }
  if (bits > 0) out.push_back(kAlphabet[(acc << (6 - bits)) & 63]);
  while (out.size() % 4) out.push_back('=');
  return out;
}

std::optional<std::vector<std::uint8_t>> base64_decode(const std::string& text) {
  std::vector<std::uint8_t> out;
  std::uint32_t acc = 0;
  int bits = 0;
  std::size_t i = 0;
  for (; i < text.size() && text[i] != '='; ++i) {
    const char* p = std::char_traits<char>::find(kAlphabet, 64, text[i]);
    if (!p) return std::nullopt;
    acc = (acc << 6) | static_cast<std::uint32_t>(p - kAlphabet);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out.push_back(static_cast<std::uint8_t>((acc >> bits) & 0xFF));
    }
  }
  for (; i < text.size(); ++i)
    if (text[i] != '=') return std::nullopt;
  return out;
}

namespace {
std::string to_hex(const std::uint8_t* bytes, std::size_t n) {
  static constexpr char kHex[] = "0123456789abcdef";
  std::string out;
  for (std::size_t i = 0; i < n; ++i) {
    out.push_back(kHex[bytes[i] >> 4]);
    out.push_back(kHex[bytes[i] & 15]);
  }
  return out;
}
}  // namespace

std::string random_hex(std::size_t n_bytes) {
  const auto bytes = random_bytes(n_bytes);
  return to_hex(bytes.data(), bytes.size());
}

PasswordHash PasswordHash::create(const std::string& password, int iterations) {
  if (iterations < kMinIterations) throw std::invalid_argument("PBKDF2 needs at least 10000 iterations");
  PasswordHash h;
  h.iterations = iterations;
  h.salt = random_bytes(16);
  h.hash = derive(password, h.salt, iterations, 32);
  return h;
}

std::optional<PasswordHash> PasswordHash::parse(const std::string& encoded) {
  std::vector<std::string> parts;
  std::size_t pos = 0;
  while (true) {
    const std::size_t end = encoded.find('$', pos);
    parts.push_back(encoded.substr(pos, end == std::string::npos ? std::string::npos : end - pos));
    if (end == std::string::npos) break;
    pos = end + 1;
  }
  if (parts.size() != 4 || parts[0] != kScheme) return std::nullopt;
  PasswordHash h;
  try {
    std::size_t used = 0;
    h.iterations = std::stoi(parts[1], &used);
    if (used != parts[1].size()) return std::nullopt;
  } catch (const std::exception&) {
    return std::nullopt;
  }
  auto salt = base64_decode(parts[2]);
  auto hash = base64_decode(parts[3]);
  if (h.iterations < kMinIterations || !salt || !hash || salt->size() < 8 || hash->size() < 16) return std::nullopt;
  h.salt = std::move(*salt);
  h.hash = std::move(*hash);
  return h;
}

std::string PasswordHash::encode() const {
  return std::string(kScheme) + "$" + std::to_string(iterations) + "$" + base64_encode(salt) + "$" + base64_encode(hash);
}

bool PasswordHash::verify(const std::string& password) const {
  const auto candidate = derive(password, salt, iterations, hash.size());
  return CRYPTO_memcmp(candidate.data(), hash.data(), hash.size()) == 0;
}

std::string sha256_hex(const std::string& text) {
  std::uint8_t digest[EVP_MAX_MD_SIZE];
  unsigned int length = 0;
  if (EVP_Digest(text.data(), text.size(), digest, &length, EVP_sha256(), nullptr) != 1)
    throw std::runtime_error("OpenSSL SHA-256 failed");
  return to_hex(digest, length);
}

}  // namespace labo::server
