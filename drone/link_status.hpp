#pragma once
// What every real-time link (ArdroneLink, TelloLink) does with its state, in one place: the state a
// silence of the drone's telemetry means, the state kept and each change reported (a log line, the
// counter link_state_<state>, a recording note the replay acts on, the listener's event), and the
// telemetry and video rates of the last second for LinkStatistics.
#include <functional>
#include <mutex>
#include <string_view>

#include "core/log.hpp"
#include "drone/ardrone2/link_counters.hpp"
#include "drone/drone_link.hpp"
#include "drone/replay/recording.hpp"

namespace labo {

// Connecting before any telemetry (last_t < 0), then Connected, Degraded after `degraded_after_s`
// of silence, Lost after `lost_after_s`.
LinkState state_after_silence(Seconds last_t, Seconds t, Seconds degraded_after_s, Seconds lost_after_s);

class LinkStatus {
 public:
  LinkStatus(const Logger& logger, ardrone2::LinkCounters& counters) : logger_(logger), counters_(counters) {}
  LinkState state() const;
  // A change is reported: logged, counted, noted in `recorder` (may be null), then `notify(s, t)`.
  void set(LinkState s, Seconds t, replay::RecordingWriter* recorder, const std::function<void(LinkState, Seconds)>& notify);
  // Call often: once a second sets the counters' rates from `packets_kind` and "video_decoded".
  void update_rates(Seconds t, std::string_view packets_kind);

 private:
  const Logger& logger_;
  ardrone2::LinkCounters& counters_;
  mutable std::mutex mutex_;
  LinkState state_ = LinkState::Disconnected;
  Seconds rate_t_ = -1;  // rates' thread only
  std::uint64_t last_packets_ = 0, last_frames_ = 0;
};

}  // namespace labo
