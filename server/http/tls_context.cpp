#include "server/http/tls_context.hpp"

#include <stdexcept>

namespace labo::server {

namespace ssl = boost::asio::ssl;

std::unique_ptr<ssl::context> make_tls_context(const TlsSettings& tls) {
  if (!tls.enabled()) return nullptr;
  auto context = std::make_unique<ssl::context>(ssl::context::tls_server);
  context->set_options(ssl::context::default_workarounds | ssl::context::no_sslv2 | ssl::context::no_sslv3 |
                       ssl::context::no_tlsv1 | ssl::context::no_tlsv1_1 | ssl::context::single_dh_use);
  boost::system::error_code ec;
  context->use_certificate_chain_file(tls.cert_file.string(), ec);
  if (ec) throw std::runtime_error("server.tls.cert_file " + tls.cert_file.string() + ": not a PEM certificate chain (" + ec.message() + ")");
  context->use_private_key_file(tls.key_file.string(), ssl::context::pem, ec);
  // A key that is not the certificate's fails here ("key values mismatch") rather than at each client's handshake.
  if (ec || SSL_CTX_check_private_key(context->native_handle()) != 1)
    throw std::runtime_error("server.tls.key_file " + tls.key_file.string() + ": not a PEM private key of " +
                             tls.cert_file.string() + " (" + (ec ? ec.message() : std::string("key values mismatch")) + ")");
  return context;
}

}  // namespace labo::server
