#include "server/lab/server_metrics.hpp"

#include <sstream>

namespace labo::server {

namespace {
template <typename T>
void emit(std::ostringstream& out, const char* name, const char* type, const char* help, const std::atomic<T>& v) {
  out << "# HELP " << name << ' ' << help << "\n# TYPE " << name << ' ' << type << '\n'
      << name << ' ' << v.load(std::memory_order_relaxed) << '\n';
}
}  // namespace

std::string ServerMetrics::prometheus_text(const std::string& extra) const {
  std::ostringstream o;
  emit(o, "labodrone_http_requests_total", "counter", "HTTP requests handled.", http_requests);
  emit(o, "labodrone_http_client_errors_total", "counter", "HTTP responses with a 4xx status.", http_errors_4xx);
  emit(o, "labodrone_http_server_errors_total", "counter", "HTTP responses with a 5xx status.", http_errors_5xx);
  emit(o, "labodrone_ws_connections_total", "counter", "WebSocket connections accepted.", ws_connections_total);
  emit(o, "labodrone_ws_clients", "gauge", "WebSocket clients connected now.", ws_clients);
  emit(o, "labodrone_ws_messages_in_total", "counter", "WebSocket messages received.", ws_messages_in);
  emit(o, "labodrone_ws_events_out_total", "counter", "JSON events written to clients.", ws_events_out);
  emit(o, "labodrone_ws_events_dropped_total", "counter", "JSON events dropped on full client queues.", ws_events_dropped);
  emit(o, "labodrone_ws_frames_out_total", "counter", "Video frames written to clients.", ws_frames_out);
  emit(o, "labodrone_ws_frames_skipped_total", "counter", "Video frames replaced before a slow client took them.", ws_frames_skipped);
  emit(o, "labodrone_ws_units_out_total", "counter", "H.264 access units written to clients.", ws_units_out);
  emit(o, "labodrone_ws_units_skipped_total", "counter", "H.264 access units dropped while a client waited for an IDR.", ws_units_skipped);
  emit(o, "labodrone_ws_keyframe_waits_total", "counter", "Times a client fell behind and dropped to the next IDR.", ws_keyframe_waits);
  emit(o, "labodrone_ws_slow_disconnects_total", "counter", "Clients disconnected for a backlog that stayed full.", ws_slow_disconnects);
  emit(o, "labodrone_ws_bytes_out_total", "counter", "Bytes written to WebSocket clients.", ws_bytes_out);
  emit(o, "labodrone_frames_published_total", "counter", "Annotated frames encoded and published.", frames_published);
  emit(o, "labodrone_access_units_published_total", "counter", "H.264 access units passed on from the drone.", access_units_published);
  emit(o, "labodrone_low_units_published_total", "counter", "H.264 access units of the shared low rendition encoded.", low_units_published);
  emit(o, "labodrone_ws_rendition_changes_total", "counter", "Times an H.264 viewer was moved between the drone's stream and the low rendition.", ws_rendition_changes);
  emit(o, "labodrone_low_rendition_viewers", "gauge", "H.264 viewers that need the low rendition now.", low_rendition_viewers);
  emit(o, "labodrone_reading_views_published_total", "counter", "Rectified panel views published.", reading_views_published);
  emit(o, "labodrone_commands_accepted_total", "counter", "Mission commands accepted.", commands_accepted);
  emit(o, "labodrone_commands_rejected_total", "counter", "Mission commands rejected.", commands_rejected);
  emit(o, "labodrone_rate_limited_total", "counter", "Messages refused by a rate limit.", rate_limited);
  emit(o, "labodrone_logins_total", "counter", "Successful logins.", logins_ok);
  emit(o, "labodrone_login_failures_total", "counter", "Refused logins.", logins_failed);
  emit(o, "labodrone_queue_length", "gauge", "Clients waiting for control.", queue_length);
  return o.str() + extra;
}

}  // namespace labo::server
