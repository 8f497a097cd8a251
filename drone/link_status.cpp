#include "drone/link_status.hpp"

#include <string>

namespace labo {

using replay::RecordingWriter;
using replay::kNoteLinkStatePrefix;


LinkState state_after_silence(Seconds last_t, Seconds t, Seconds degraded_after_s, Seconds lost_after_s) {
  if (last_t < 0) return LinkState::Connecting;
  const Seconds silent = t - last_t;
  return silent > lost_after_s ? LinkState::Lost : silent > degraded_after_s ? LinkState::Degraded : LinkState::Connected;
}

LinkState LinkStatus::state() const {
  std::lock_guard lock(mutex_);
  return state_;
}

void LinkStatus::set(LinkState s, Seconds t, RecordingWriter* recorder,
                     const std::function<void(LinkState, Seconds)>& notify) {
  {
    std::lock_guard lock(mutex_);
    if (state_ == s) return;
    state_ = s;
  }
  logger_.info(t, "link state").kv("state", to_string(s));
  counters_.add("link_state_" + to_string(s));
  if (recorder) recorder->note(t, std::string(kNoteLinkStatePrefix) + to_string(s));
  if (notify) notify(s, t);
}

void LinkStatus::update_rates(Seconds t, std::string_view packets_kind) {
  if (rate_t_ < 0) rate_t_ = t;
  if (t - rate_t_ < 1.0) return;
  const auto packets = counters_.get(packets_kind), frames = counters_.get("video_decoded");
  counters_.set_rates(static_cast<double>(packets - last_packets_) / (t - rate_t_),
                      static_cast<double>(frames - last_frames_) / (t - rate_t_));
  last_packets_ = packets;
  last_frames_ = frames;
  rate_t_ = t;
}

}  // namespace labo
