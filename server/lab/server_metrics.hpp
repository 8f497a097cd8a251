#pragma once
// Counters and gauges of the web server, read by GET /metrics (Prometheus text format 0.0.4) and
// the admin page. Lock-free: every field is an atomic bumped from any thread.
#include <atomic>
#include <cstdint>
#include <string>

namespace labo::server {

struct ServerMetrics {
  std::atomic<std::uint64_t> http_requests{0};
  std::atomic<std::uint64_t> http_errors_4xx{0};
  std::atomic<std::uint64_t> http_errors_5xx{0};
  std::atomic<std::uint64_t> ws_connections_total{0};
  std::atomic<std::int64_t> ws_clients{0};
  std::atomic<std::uint64_t> ws_messages_in{0};
  std::atomic<std::uint64_t> ws_events_out{0};
  std::atomic<std::uint64_t> ws_events_dropped{0};
  std::atomic<std::uint64_t> ws_frames_out{0};
  std::atomic<std::uint64_t> ws_frames_skipped{0};  // replaced in a client's slot before being sent
  std::atomic<std::uint64_t> ws_units_out{0};        // H.264 access units written
  std::atomic<std::uint64_t> ws_units_skipped{0};    // dropped while a client waited for the next IDR
  std::atomic<std::uint64_t> ws_keyframe_waits{0};   // a client fell behind and dropped to the next IDR
  std::atomic<std::uint64_t> ws_slow_disconnects{0};
  std::atomic<std::uint64_t> ws_bytes_out{0};
  std::atomic<std::uint64_t> frames_published{0};
  std::atomic<std::uint64_t> access_units_published{0};      // the drone's own stream
  std::atomic<std::uint64_t> low_units_published{0};         // the shared low rendition
  std::atomic<std::uint64_t> ws_rendition_changes{0};        // a viewer moved between renditions
  std::atomic<std::int64_t> low_rendition_viewers{0};
  std::atomic<std::uint64_t> reading_views_published{0};
  std::atomic<std::uint64_t> commands_accepted{0};
  std::atomic<std::uint64_t> commands_rejected{0};
  std::atomic<std::uint64_t> rate_limited{0};
  std::atomic<std::uint64_t> logins_ok{0};
  std::atomic<std::uint64_t> logins_failed{0};
  std::atomic<std::int64_t> queue_length{0};

  // Prometheus text exposition; `extra` is appended (gauges computed by the caller).
  std::string prometheus_text(const std::string& extra = {}) const;
};

}  // namespace labo::server
