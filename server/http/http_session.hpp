#pragma once
// One HTTP/1.1 connection on its own strand: reads a request header, refuses oversize bodies from
// Content-Length before reading them (Boost 1.74's body_limit misses that case), hands WebSocket
// upgrades of /ws to a WebSocketSession after checking the session, and answers everything else
// through the RestApi. One request at a time per connection, keep-alive honoured.
#include <boost/asio/ip/tcp.hpp>
#include <memory>

namespace labo::server {

struct ServerContext;

void start_http_session(boost::asio::ip::tcp::socket&& socket, std::shared_ptr<ServerContext> ctx);

}  // namespace labo::server
