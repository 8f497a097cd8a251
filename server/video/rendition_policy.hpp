#pragma once
// Which H.264 rendition one viewer should get: the drone's own stream (the source) or the server's
// one shared lower-rate encode (the low rendition), from what the viewer's connection carries.
// Pure logic, time passed in: the WebSocket session feeds it a sample of its byte counters a few
// times a second.
//
// Down: the viewer lags. Its backlog is every byte given to it and not yet acknowledged by its peer:
// units queued in its ring or being written, and the socket's send queue (written, not yet acked by
// TCP). Divided by the rate the stream offers, that is how many seconds of video the viewer is
// behind. A lag above `max_lag_s` for `lag_hold_s`, or a ring overflow (the viewer dropped to the
// next IDR), moves it to the low rendition.
// Up: a stream a viewer receives at its own rate cannot say whether a faster one would fit, so the
// source is tried again (a probe) once the viewer has carried the low rendition without lag for
// `probe_after_s`; a probe that fails within `probe_window_s` doubles that wait (up to
// `max_probe_after_s`), one that holds resets it.
// The throughput shown to the viewer is the acknowledged bytes per second over `window_s`.
#include <cstdint>
#include <deque>
#include <string>

#include "server/video/rendition.hpp"

namespace labo::server {

struct RenditionPolicySettings {
  double window_s = 2.0;           // throughput and offered rate measured over
  double max_lag_s = 0.5;          // seconds of stream behind before the viewer goes down
  double lag_hold_s = 0.5;         // ... for this long
  double probe_after_s = 15;       // lag-free on the low rendition this long: try the source
  double max_probe_after_s = 120;  // the wait between probes after failed ones, at most
  double probe_window_s = 10;      // a probe that goes down within this failed
};

// The session's counters at one instant; all but t_s only grow, except the two backlog gauges.
struct ViewerSample {
  double t_s = 0;                    // steady clock
  std::uint64_t video_offered = 0;   // bytes of video (units and geometry) given to the viewer, kept or dropped
  std::uint64_t written = 0;         // bytes the socket accepted (completed writes)
  std::uint64_t unacked = 0;         // of those, not yet acknowledged by the peer (the send queue)
  std::uint64_t pending = 0;         // bytes queued in the session or being written
  std::uint64_t overflows = 0;       // times its ring overflowed and it dropped to the next IDR
};

class RenditionPolicy {
 public:
  explicit RenditionPolicy(RenditionPolicySettings settings = {}, RenditionChoice choice = RenditionChoice::Auto);

  // A new sample; returns the rendition the viewer should get from now on.
  Rendition update(const ViewerSample& sample);
  // A new choice by the viewer (a pinned rendition at once; auto starts from the source).
  void choose(RenditionChoice choice, double t_s);

  Rendition rendition() const { return rendition_; }
  RenditionChoice choice() const { return choice_; }
  double throughput_kbps() const { return throughput_kbps_; }
  double lag_s() const { return lag_s_; }
  double probe_after_s() const { return probe_after_s_; }
  // Why the viewer is on its rendition, for the page.
  const std::string& reason() const { return reason_; }

 private:
  void measure(const ViewerSample& s);
  void go(Rendition r, double t_s, std::string reason);

  RenditionPolicySettings settings_;
  RenditionChoice choice_;
  Rendition rendition_;
  std::deque<ViewerSample> window_;  // the samples of the last window_s (a few per second)
  double throughput_kbps_ = 0, lag_s_ = 0;
  double lagging_since_ = -1;   // < 0: not lagging
  double calm_since_ = -1;      // on the low rendition without lag since
  double switched_at_ = -1e9;   // the last change of rendition
  double probe_after_s_;
  bool probing_ = false;        // on the source because of a probe
  std::uint64_t overflows_seen_ = 0;
  std::string reason_;
};

}  // namespace labo::server
