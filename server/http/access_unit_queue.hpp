#pragma once
// One viewer's H.264 access units waiting to be written, each with its overlay geometry: a ring of
// at most `capacity` units. H.264 frames depend on the ones before them, so a unit cannot simply be
// replaced by a newer one like a JPEG frame: a viewer that falls behind (a unit arrives with the
// ring full) drops everything queued and waits for the next IDR, where its decoder can start again.
// A new viewer waits for an IDR too. The viewer's lag is therefore bounded by `capacity` frames and
// its memory by `capacity` shared messages. Single-threaded (the session's strand); no allocation
// after construction.
#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "server/lab/flight_service.hpp"

namespace labo::server {

class AccessUnitQueue {
 public:
  explicit AccessUnitQueue(std::size_t capacity);

  struct PushResult {
    bool queued = false;
    std::size_t dropped = 0;   // units dropped: this one (waiting for an IDR) and/or the queued ones
    bool fell_behind = false;  // the ring was full: the viewer now waits for the next IDR
  };
  PushResult push(const WireAccessUnit& unit);

  // The next message to write (a unit's geometry, text, then the unit itself, binary), or nullptr.
  std::shared_ptr<const std::string> pop(bool& binary);
  bool empty() const { return count_ == 0; }
  std::size_t size() const { return count_; }
  bool waiting_for_keyframe() const { return waiting_for_keyframe_; }
  // Bytes of the messages queued (units and their geometry): part of the viewer's backlog.
  std::size_t bytes() const { return bytes_; }
  // Forget everything queued and wait for the next IDR (a new subscription).
  void restart();

 private:
  struct Entry {
    std::shared_ptr<const std::string> geometry, wire;
  };
  void clear();

  std::vector<Entry> ring_;
  std::size_t head_ = 0, count_ = 0, bytes_ = 0;
  bool waiting_for_keyframe_ = true;
};

}  // namespace labo::server
