#include "server/video/rendition_policy.hpp"

#include <algorithm>
#include <cstdio>

namespace labo::server {

namespace {
std::string format(const char* pattern, double a, double b = 0) {
  char text[160];
  std::snprintf(text, sizeof text, pattern, a, b);
  return text;
}
}  // namespace

RenditionPolicy::RenditionPolicy(RenditionPolicySettings settings, RenditionChoice choice)
    : settings_(settings),
      choice_(choice),
      rendition_(choice == RenditionChoice::Low ? Rendition::Low : Rendition::Source),
      probe_after_s_(settings.probe_after_s) {
  choose(choice, 0);
}

void RenditionPolicy::choose(RenditionChoice choice, double t_s) {
  choice_ = choice;
  probing_ = false;
  probe_after_s_ = settings_.probe_after_s;
  switch (choice) {
    case RenditionChoice::Low: return go(Rendition::Low, t_s, "chosen by the viewer");
    case RenditionChoice::Source: return go(Rendition::Source, t_s, "chosen by the viewer");
    case RenditionChoice::Auto: return go(Rendition::Source, t_s, "the drone's stream until the link says otherwise");
  }
}

void RenditionPolicy::go(Rendition r, double t_s, std::string reason) {
  rendition_ = r;
  switched_at_ = t_s;
  lagging_since_ = calm_since_ = -1;
  reason_ = std::move(reason);
}

void RenditionPolicy::measure(const ViewerSample& s) {
  window_.push_back(s);
  while (window_.size() > 2 && s.t_s - window_[1].t_s >= settings_.window_s) window_.pop_front();
  const ViewerSample& first = window_.front();
  const double dt = s.t_s - first.t_s;
  if (dt <= 0) return;
  const double acked = static_cast<double>((s.written - s.unacked) - (first.written - first.unacked));
  throughput_kbps_ = acked * 8 / 1000 / dt;
  const double offered_per_s = static_cast<double>(s.video_offered - first.video_offered) / dt;
  const double backlog = static_cast<double>(s.pending + s.unacked);
  lag_s_ = offered_per_s > 0 ? backlog / offered_per_s : 0;
}

Rendition RenditionPolicy::update(const ViewerSample& s) {
  measure(s);
  const bool overflow = s.overflows > overflows_seen_;
  overflows_seen_ = s.overflows;
  if (choice_ != RenditionChoice::Auto) return rendition_;
  const double t = s.t_s;
  const bool lagging = lag_s_ > settings_.max_lag_s;
  if (!lagging) lagging_since_ = -1;
  else if (lagging_since_ < 0) lagging_since_ = t;

  if (rendition_ == Rendition::Source) {
    if (overflow || (lagging && t - lagging_since_ >= settings_.lag_hold_s)) {
      if (probing_ && t - switched_at_ < settings_.probe_window_s)
        probe_after_s_ = std::min(2 * probe_after_s_, settings_.max_probe_after_s);
      probing_ = false;
      go(Rendition::Low, t,
         overflow ? format("the link fell a whole queue behind the drone's stream (carried %.0f kbit/s)", throughput_kbps_)
                  : format("the link carried %.0f kbit/s, %.1f s behind the drone's stream", throughput_kbps_, lag_s_));
    } else if (probing_ && t - switched_at_ >= settings_.probe_window_s) {
      probing_ = false;  // the probe held: the link carries the source again
      probe_after_s_ = settings_.probe_after_s;
    }
    return rendition_;
  }
  if (lagging || overflow) calm_since_ = -1;
  else if (calm_since_ < 0) calm_since_ = t;
  if (calm_since_ >= 0 && t - calm_since_ >= probe_after_s_) {
    probing_ = true;
    go(Rendition::Source, t, format("trying the drone's stream again after %.0f s without lag (carried %.0f kbit/s)",
                                    probe_after_s_, throughput_kbps_));
  }
  return rendition_;
}

}  // namespace labo::server
