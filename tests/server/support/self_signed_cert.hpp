#pragma once
// A self-signed certificate for 127.0.0.1 made by the test itself (OpenSSL's API: a P-256 key, one
// day of validity), written as PEM files for `server.tls`. Tests only.
#include <openssl/evp.h>
#include <openssl/pem.h>
#include <openssl/x509.h>
#include <openssl/x509v3.h>

#include <cstdio>
#include <filesystem>
#include <memory>
#include <stdexcept>

namespace labo::server::test {

struct SelfSignedCert {
  std::filesystem::path cert_file, key_file;
};

inline SelfSignedCert make_self_signed_cert(const std::filesystem::path& dir) {
  const std::unique_ptr<EVP_PKEY, decltype(&EVP_PKEY_free)> key(EVP_EC_gen("P-256"), EVP_PKEY_free);
  const std::unique_ptr<X509, decltype(&X509_free)> cert(X509_new(), X509_free);
  if (!key || !cert) throw std::runtime_error("OpenSSL: cannot make a key or a certificate");
  X509_set_version(cert.get(), 2);
  ASN1_INTEGER_set(X509_get_serialNumber(cert.get()), 1);
  X509_gmtime_adj(X509_getm_notBefore(cert.get()), -60);
  X509_gmtime_adj(X509_getm_notAfter(cert.get()), 24 * 3600);
  X509_set_pubkey(cert.get(), key.get());
  X509_NAME* name = X509_get_subject_name(cert.get());
  X509_NAME_add_entry_by_txt(name, "CN", MBSTRING_ASC, reinterpret_cast<const unsigned char*>("127.0.0.1"), -1, -1, 0);
  X509_set_issuer_name(cert.get(), name);
  X509V3_CTX ctx;
  X509V3_set_ctx_nodb(&ctx);
  X509V3_set_ctx(&ctx, cert.get(), cert.get(), nullptr, nullptr, 0);
  const std::unique_ptr<X509_EXTENSION, decltype(&X509_EXTENSION_free)> san(
      X509V3_EXT_conf_nid(nullptr, &ctx, NID_subject_alt_name, "IP:127.0.0.1"), X509_EXTENSION_free);
  X509_add_ext(cert.get(), san.get(), -1);
  if (X509_sign(cert.get(), key.get(), EVP_sha256()) == 0) throw std::runtime_error("OpenSSL: cannot sign the certificate");
  SelfSignedCert out{dir / "cert.pem", dir / "key.pem"};
  const auto write = [](const std::filesystem::path& file, auto writer) {
    std::FILE* f = std::fopen(file.c_str(), "w");
    if (!f || !writer(f)) throw std::runtime_error("cannot write " + file.string());
    std::fclose(f);
  };
  write(out.cert_file, [&](std::FILE* f) { return PEM_write_X509(f, cert.get()) == 1; });
  write(out.key_file, [&](std::FILE* f) { return PEM_write_PrivateKey(f, key.get(), nullptr, nullptr, 0, nullptr, nullptr) == 1; });
  return out;
}

}  // namespace labo::server::test
