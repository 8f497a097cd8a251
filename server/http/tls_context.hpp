#pragma once
// The TLS side of the server (`server.tls`): OpenSSL through Boost.Asio, TLS 1.2 and later, the
// certificate chain and key read from PEM files.
#include <boost/asio/ssl/context.hpp>
#include <memory>

#include "server/server_settings.hpp"

namespace labo::server {

// Null when TLS is off. Throws std::runtime_error naming the file that could not be used.
std::unique_ptr<boost::asio::ssl::context> make_tls_context(const TlsSettings& tls);

}  // namespace labo::server
