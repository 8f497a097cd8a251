#pragma once
// The AR.Drone CONFIG handshake, one key at a time, without I/O (ArdroneLink's control thread ticks
// it every 30 ms): send CONFIG_IDS + CONFIG, wait for navdata state bit 6 (resend after a timeout),
// answer CTRL 5 until the bit clears, then the next key. A stale bit 6 is cleared before sending.
#include <deque>
#include <optional>
#include <string>

#include "core/time.hpp"
#include "drone/ardrone2/at_command.hpp"

namespace labo::ardrone2 {

struct ConfigEntry {
  std::string key, value;
};

struct ConfigTick {
  bool sent = false;                      // a CONFIG went out this tick
  std::optional<ConfigEntry> acked;       // acknowledged this tick
  std::optional<std::string> timed_out;   // key not acknowledged in time (resent next tick)
};

class ConfigHandshake {
 public:
  explicit ConfigHandshake(Seconds ack_timeout_s = 0.5) : ack_timeout_s_(ack_timeout_s) {}
  void push_back(ConfigEntry entry) { queue_.push_back(std::move(entry)); }
  void push_front(ConfigEntry entry) { queue_.push_front(std::move(entry)); }
  // Starts over (reconnection): the key in flight, if any, is sent again.
  void restart() { phase_ = Phase::Idle; }
  std::size_t pending() const { return queue_.size(); }

  // `ack` = navdata state bit 6; `alive` = navdata is fresh (a CONFIG sent into silence is wasted).
  ConfigTick tick(Seconds t, bool ack, bool alive, AtCommandEncoder& encoder, std::string& out);

 private:
  enum class Phase { Idle, AwaitAck, AwaitAckClear };
  Seconds ack_timeout_s_;
  std::deque<ConfigEntry> queue_;
  Phase phase_ = Phase::Idle;
  Seconds sent_t_ = 0;
};

}  // namespace labo::ardrone2
