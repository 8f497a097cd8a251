#include "server/http/websocket_session.hpp"

#include <boost/asio/dispatch.hpp>
#include <boost/asio/post.hpp>
#include <boost/beast/ssl.hpp>
#include <boost/beast/websocket/ssl.hpp>
#include <linux/sockios.h>
#include <sys/ioctl.h>

#include "server/lab/lab_messages.hpp"
#include "server/lab/remote_lab.hpp"

namespace labo::server {

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace websocket = beast::websocket;

template <class NextLayer>
WebSocketSession<NextLayer>::WebSocketSession(NextLayer&& stream, ClientId id, SessionInfo session,
                                              std::shared_ptr<RemoteLab> lab, const ClientLimits& limits,
                                              ServerMetrics& metrics)
    : ws_(std::move(stream)),
      watchdog_(ws_.get_executor()),
      id_(id),
      session_(std::move(session)),
      lab_(std::move(lab)),
      limits_(limits),
      metrics_(metrics),
      units_(static_cast<std::size_t>(limits.video_queue_frames)),
      policy_(RenditionPolicySettings{.max_lag_s = limits.rendition_max_lag_s, .probe_after_s = limits.rendition_probe_after_s}) {}

namespace {
double steady_s(std::chrono::steady_clock::time_point t) { return std::chrono::duration<double>(t.time_since_epoch()).count(); }
}  // namespace

template <class NextLayer>
WebSocketSession<NextLayer>::~WebSocketSession() {
  if (joined_) {
    lab_->leave(id_);
    metrics_.ws_clients--;
  }
}

template <class NextLayer>
void WebSocketSession<NextLayer>::accept(beast::http::request<beast::http::string_body> upgrade) {
  // tcp_stream timeouts must not apply to a websocket: the websocket's own (with pings) take over.
  beast::get_lowest_layer(ws_).expires_never();
  if (limits_.send_buffer_bytes > 0) {
    beast::error_code ignored;  // a kernel that refuses keeps its own size: the backlog is measured either way
    beast::get_lowest_layer(ws_).socket().set_option(asio::socket_base::send_buffer_size(limits_.send_buffer_bytes), ignored);
  }
  ws_.set_option(websocket::stream_base::timeout::suggested(beast::role_type::server));
  ws_.set_option(websocket::stream_base::decorator(
      [](websocket::response_type& res) { res.set(beast::http::field::server, "labodrone"); }));
  ws_.read_message_max(static_cast<std::size_t>(limits_.max_message_bytes));
  ws_.auto_fragment(false);
  ws_.async_accept(upgrade, beast::bind_front_handler(&WebSocketSession::on_accept, this->shared_from_this()));
}

template <class NextLayer>
void WebSocketSession<NextLayer>::on_accept(beast::error_code ec) {
  if (ec) return;
  joined_ = true;
  metrics_.ws_clients++;
  metrics_.ws_connections_total++;
  lab_->join(this->shared_from_this());
  arm_watchdog();
  do_read();
}

template <class NextLayer>
void WebSocketSession<NextLayer>::do_read() {
  ws_.async_read(read_buffer_, beast::bind_front_handler(&WebSocketSession::on_read, this->shared_from_this()));
}

template <class NextLayer>
void WebSocketSession<NextLayer>::on_read(beast::error_code ec, std::size_t) {
  if (ec == websocket::error::message_too_big) {
    // Beast has already failed the stream with close code 1009 (message too big).
    close_now("message larger than " + std::to_string(limits_.max_message_bytes) + " bytes");
    return;
  }
  if (ec) {  // closed by the peer, or by us: the destructor leaves the lab
    closed_ = true;
    watchdog_.cancel();
    return;
  }
  metrics_.ws_messages_in++;
  if (!ws_.got_text()) {
    queue_event(error_message(400, "binary messages are not accepted: send JSON text"));
  } else {
    lab_->on_message(*this, beast::buffers_to_string(read_buffer_.data()));
  }
  read_buffer_.consume(read_buffer_.size());
  do_read();
}

template <class NextLayer>
void WebSocketSession<NextLayer>::send_event(std::shared_ptr<const std::string> json) {
  asio::post(ws_.get_executor(), [self = this->shared_from_this(), json = std::move(json)]() mutable {
    self->queue_event(std::move(json));
  });
}

template <class NextLayer>
void WebSocketSession<NextLayer>::send_frame(std::shared_ptr<const std::string> wire) {
  asio::post(ws_.get_executor(), [self = this->shared_from_this(), wire = std::move(wire)]() mutable {
    self->store_frame(std::move(wire));
  });
}

template <class NextLayer>
void WebSocketSession<NextLayer>::send_access_unit(const WireAccessUnit& unit) {
  asio::post(ws_.get_executor(), [self = this->shared_from_this(), unit] { self->queue_unit(unit); });
}

template <class NextLayer>
void WebSocketSession<NextLayer>::send_reading_view(std::shared_ptr<const std::string> view) {
  asio::post(ws_.get_executor(), [self = this->shared_from_this(), view = std::move(view)]() mutable {
    if (self->closed_ || !self->joined_) return;
    self->reading_slot_ = std::move(view);
    self->write_next();
  });
}

template <class NextLayer>
void WebSocketSession<NextLayer>::send_replay_frame(std::shared_ptr<const std::string> wire) {
  asio::post(ws_.get_executor(), [self = this->shared_from_this(), wire = std::move(wire)]() mutable {
    if (self->closed_ || !self->joined_) return;
    self->replay_slot_ = std::move(wire);
    self->write_next();
  });
}

template <class NextLayer>
void WebSocketSession<NextLayer>::select_video(VideoPath path, RenditionChoice rendition) {
  asio::post(ws_.get_executor(), [self = this->shared_from_this(), path, rendition] {
    const bool was_h264 = self->video_ == VideoPath::H264;
    self->policy_.choose(rendition, steady_s(Clock::now()));
    if (was_h264 && path == VideoPath::H264) {
      self->switch_.aim(self->policy_.rendition());  // another rendition: switch at its next IDR, no gap
    } else {
      self->video_ = path;
      self->units_.restart();
      self->frame_slot_.reset();
      self->switch_.reset(self->policy_.rendition());
    }
    self->publish_renditions();
    if (path == VideoPath::H264)
      self->queue_event(rendition_message(self->policy_.rendition(), self->policy_.choice(), self->policy_.reason(), 0, 0));
  });
}

template <class NextLayer>
void WebSocketSession<NextLayer>::disconnect(const std::string& reason) {
  asio::post(ws_.get_executor(), [self = this->shared_from_this(), reason] { self->close_now(reason); });
}

template <class NextLayer>
void WebSocketSession<NextLayer>::queue_event(std::shared_ptr<const std::string> json) {
  if (closed_) return;
  if (events_.size() >= static_cast<std::size_t>(limits_.event_queue_messages)) {
    metrics_.ws_events_dropped++;
    if (!queue_full_since_) queue_full_since_ = Clock::now();
    return;
  }
  events_.push_back(std::move(json));
  write_next();
}

template <class NextLayer>
void WebSocketSession<NextLayer>::store_frame(std::shared_ptr<const std::string> wire) {
  if (closed_ || !joined_) return;
  if (frame_slot_) metrics_.ws_frames_skipped++;
  frame_slot_ = std::move(wire);  // overwrite: only the newest frame waits
  write_next();
}

template <class NextLayer>
void WebSocketSession<NextLayer>::queue_unit(const WireAccessUnit& unit) {
  if (closed_ || !joined_ || video_ != VideoPath::H264 || !switch_.accept(unit)) return;
  video_offered_ += (unit.wire ? unit.wire->size() : 0) + (unit.geometry ? unit.geometry->size() : 0);
  const AccessUnitQueue::PushResult r = units_.push(unit);
  metrics_.ws_units_skipped += r.dropped;
  if (r.fell_behind) {
    metrics_.ws_keyframe_waits++;
    overflows_++;
  }
  if (r.queued) write_next();
  if (switch_.needed() != renditions_published_) publish_renditions();  // the switch happened at this IDR
}

template <class NextLayer>
void WebSocketSession<NextLayer>::publish_renditions() {
  renditions_published_ = video_ == VideoPath::H264 ? switch_.needed() : RenditionSwitch::bit(Rendition::Source);
  lab_->set_renditions(id_, renditions_published_);
}

template <class NextLayer>
void WebSocketSession<NextLayer>::adapt_rendition(Clock::time_point now) {
  int unacked = 0;  // written to the socket, not yet acknowledged by the peer
  if (::ioctl(beast::get_lowest_layer(ws_).socket().native_handle(), SIOCOUTQ, &unacked) != 0) unacked = 0;
  const std::uint64_t pending = units_.bytes() + (writing_ && in_flight_ ? in_flight_->size() : 0);
  const Rendition before = policy_.rendition();
  const Rendition wanted = policy_.update({steady_s(now), video_offered_, bytes_written_,
                                          static_cast<std::uint64_t>(std::max(unacked, 0)), pending, overflows_});
  const bool changed = wanted != before;
  if (changed) {
    metrics_.ws_rendition_changes++;
    switch_.aim(wanted);
    publish_renditions();
  }
  // The page shows its rendition, why, and what its link carries: at each change and once a second.
  if (changed || ++samples_ % 4 == 0)
    queue_event(rendition_message(policy_.rendition(), policy_.choice(), policy_.reason(), policy_.throughput_kbps(), policy_.lag_s()));
}

template <class NextLayer>
void WebSocketSession<NextLayer>::write_next() {
  if (writing_ || closed_ || !joined_) return;
  // Events first (acks, emergencies, stage changes), then video: the next access unit (its geometry
  // first) or the newest JPEG frame, then the newest reading view, then a replay's newest frame.
  bool binary = false;
  if (!events_.empty()) {
    in_flight_ = std::move(events_.front());
    events_.pop_front();
    in_flight_kind_ = Outgoing::Event;
    if (events_.size() < static_cast<std::size_t>(limits_.event_queue_messages)) queue_full_since_.reset();
  } else if (!units_.empty()) {
    in_flight_ = units_.pop(binary);
    in_flight_kind_ = binary ? Outgoing::Unit : Outgoing::Geometry;
  } else if (frame_slot_) {
    in_flight_ = std::move(frame_slot_);
    frame_slot_.reset();
    in_flight_kind_ = Outgoing::Frame;
    binary = true;
  } else if (reading_slot_) {
    in_flight_ = std::move(reading_slot_);
    reading_slot_.reset();
    in_flight_kind_ = Outgoing::Reading;
    binary = true;
  } else if (replay_slot_) {
    in_flight_ = std::move(replay_slot_);
    replay_slot_.reset();
    in_flight_kind_ = Outgoing::Replay;
    binary = true;
  } else {
    return;
  }
  writing_ = true;
  write_started_ = Clock::now();
  ws_.binary(binary);
  ws_.async_write(asio::buffer(*in_flight_), beast::bind_front_handler(&WebSocketSession::on_write, this->shared_from_this()));
}

template <class NextLayer>
void WebSocketSession<NextLayer>::on_write(beast::error_code ec, std::size_t bytes) {
  writing_ = false;
  in_flight_.reset();
  if (ec) {
    close_now("write failed: " + ec.message());
    return;
  }
  metrics_.ws_bytes_out += bytes;
  bytes_written_ += bytes;
  switch (in_flight_kind_) {
    case Outgoing::Event: metrics_.ws_events_out++; break;
    case Outgoing::Frame: metrics_.ws_frames_out++; break;
    case Outgoing::Unit: metrics_.ws_units_out++; break;
    case Outgoing::Geometry:
    case Outgoing::Reading:
    case Outgoing::Replay: break;
  }
  write_next();
}

template <class NextLayer>
void WebSocketSession<NextLayer>::arm_watchdog() {
  watchdog_.expires_after(std::chrono::milliseconds(250));
  watchdog_.async_wait([self = this->shared_from_this()](beast::error_code ec) {
    if (!ec) self->on_watchdog();
  });
}

template <class NextLayer>
void WebSocketSession<NextLayer>::on_watchdog() {
  if (closed_) return;
  const auto now = Clock::now();
  const auto seconds = [](Clock::duration d) { return std::chrono::duration<double>(d).count(); };
  if (queue_full_since_ && seconds(now - *queue_full_since_) > limits_.backlog_timeout_s) {
    metrics_.ws_slow_disconnects++;
    close_now("event backlog full for more than " + std::to_string(limits_.backlog_timeout_s) + " s");
    return;
  }
  if (writing_ && seconds(now - write_started_) > limits_.write_timeout_s) {
    metrics_.ws_slow_disconnects++;
    close_now("a write pending for more than " + std::to_string(limits_.write_timeout_s) + " s");
    return;
  }
  if (video_ == VideoPath::H264) adapt_rendition(now);
  arm_watchdog();
}

template <class NextLayer>
void WebSocketSession<NextLayer>::close_now(const std::string& reason) {
  if (closed_) return;
  closed_ = true;
  lab_->log_disconnect(id_, reason);
  events_.clear();
  frame_slot_.reset();
  reading_slot_.reset();
  units_.restart();
  watchdog_.cancel();
  // Close the TCP socket itself: a websocket close handshake would wait behind a stuck write.
  beast::error_code ignored;
  beast::get_lowest_layer(ws_).socket().shutdown(asio::ip::tcp::socket::shutdown_both, ignored);
  beast::get_lowest_layer(ws_).socket().close(ignored);
}

template class WebSocketSession<beast::tcp_stream>;
template class WebSocketSession<beast::ssl_stream<beast::tcp_stream>>;

}  // namespace labo::server
