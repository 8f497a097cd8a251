#pragma once
// One WebSocket client (Beast 1.74). Runs on its connection's strand. A read is always pending, so
// pings, pongs and close frames are handled even for view-only spectators. Outgoing traffic goes
// through a bounded queue of JSON events, and video by the path the client chose: a one-frame JPEG
// slot that a newer frame overwrites, or a bounded queue of H.264 access units that drops to the
// next IDR (AccessUnitQueue). A slow viewer loses frames, never memory. A client whose event queue
// stays full, or whose write stays pending, past its limit is disconnected. `NextLayer` is the
// connection under the WebSocket: a plain TCP stream, or TLS over it (PlainWebSocket, TlsWebSocket).
// An H.264 viewer's link is measured a few times a second (its backlog: queued bytes and the socket's
// unacknowledged send queue) and the viewer moved between the drone's stream and the shared low
// rendition (RenditionPolicy, RenditionSwitch).
#include <boost/asio/steady_timer.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/ssl/ssl_stream.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>
#include <chrono>
#include <deque>
#include <memory>
#include <string>

#include "server/http/access_unit_queue.hpp"
#include "server/lab/lab_client.hpp"
#include "server/lab/server_metrics.hpp"
#include "server/server_settings.hpp"
#include "server/video/rendition_policy.hpp"
#include "server/video/rendition_switch.hpp"

namespace labo::server {

class RemoteLab;

template <class NextLayer>
class WebSocketSession final : public LabClient, public std::enable_shared_from_this<WebSocketSession<NextLayer>> {
 public:
  WebSocketSession(NextLayer&& stream, ClientId id, SessionInfo session,
                   std::shared_ptr<RemoteLab> lab, const ClientLimits& limits, ServerMetrics& metrics);
  ~WebSocketSession() override;

  void accept(boost::beast::http::request<boost::beast::http::string_body> upgrade);

  ClientId id() const override { return id_; }
  const SessionInfo& session() const override { return session_; }
  void send_event(std::shared_ptr<const std::string> json) override;
  void send_frame(std::shared_ptr<const std::string> wire) override;
  void send_access_unit(const WireAccessUnit& unit) override;
  void send_reading_view(std::shared_ptr<const std::string> view) override;
  void send_replay_frame(std::shared_ptr<const std::string> wire) override;
  void select_video(VideoPath path, RenditionChoice rendition) override;
  void disconnect(const std::string& reason) override;

 private:
  using Clock = std::chrono::steady_clock;
  void on_accept(boost::beast::error_code ec);
  void do_read();
  void on_read(boost::beast::error_code ec, std::size_t bytes);
  void queue_event(std::shared_ptr<const std::string> json);
  void store_frame(std::shared_ptr<const std::string> wire);
  void queue_unit(const WireAccessUnit& unit);
  void write_next();
  void on_write(boost::beast::error_code ec, std::size_t bytes);
  void arm_watchdog();
  void on_watchdog();
  // The H.264 viewer's link sampled, its rendition decided; the page told now and then.
  void adapt_rendition(Clock::time_point now);
  void publish_renditions();
  void close_now(const std::string& reason);

  boost::beast::websocket::stream<NextLayer> ws_;
  boost::beast::flat_buffer read_buffer_;
  boost::asio::steady_timer watchdog_;
  ClientId id_;
  SessionInfo session_;
  std::shared_ptr<RemoteLab> lab_;
  ClientLimits limits_;
  ServerMetrics& metrics_;

  std::deque<std::shared_ptr<const std::string>> events_;
  std::shared_ptr<const std::string> frame_slot_;
  std::shared_ptr<const std::string> reading_slot_;  // the newest reading view
  std::shared_ptr<const std::string> replay_slot_;   // the newest frame of a replayed recording
  AccessUnitQueue units_;
  VideoPath video_ = VideoPath::Jpeg;
  RenditionPolicy policy_;
  RenditionSwitch switch_;
  unsigned renditions_published_ = RenditionSwitch::bit(Rendition::Source);
  std::uint64_t video_offered_ = 0, bytes_written_ = 0, overflows_ = 0;
  int samples_ = 0;
  enum class Outgoing { Event, Frame, Geometry, Unit, Reading, Replay };
  std::shared_ptr<const std::string> in_flight_;  // kept alive while its write runs
  Outgoing in_flight_kind_ = Outgoing::Event;
  bool writing_ = false;
  bool joined_ = false;
  bool closed_ = false;
  Clock::time_point write_started_{};
  std::optional<Clock::time_point> queue_full_since_;
};

using PlainWebSocket = WebSocketSession<boost::beast::tcp_stream>;
using TlsWebSocket = WebSocketSession<boost::beast::ssl_stream<boost::beast::tcp_stream>>;

}  // namespace labo::server
