#pragma once
// Which rendition's units one H.264 viewer takes. A viewer moves from one rendition to the other only
// at an IDR of the one it moves to: until that IDR it keeps getting the units of the one it is on, so
// its decoder never waits with nothing to show. Single-threaded (the session's strand).
#include "server/lab/flight_service.hpp"

namespace labo::server {

class RenditionSwitch {
 public:
  Rendition current() const { return current_; }
  Rendition target() const { return target_; }
  void aim(Rendition r) { target_ = r; }
  // Start over on `r` (a new subscription): the viewer waits for r's next IDR.
  void reset(Rendition r) { current_ = target_ = r; }

  // Whether `unit` goes to the viewer: one of the current rendition, or the target's IDR, where the
  // viewer switches.
  bool accept(const WireAccessUnit& unit) {
    if (unit.rendition == target_ && target_ != current_ && unit.keyframe) current_ = target_;
    return unit.rendition == current_;
  }

  // The renditions whose units the viewer needs now, as bits (1 << Rendition): the one it is on and
  // the one it moves to.
  unsigned needed() const { return bit(current_) | bit(target_); }
  static unsigned bit(Rendition r) { return 1u << static_cast<unsigned>(r); }

 private:
  Rendition current_ = Rendition::Source, target_ = Rendition::Source;
};

}  // namespace labo::server
