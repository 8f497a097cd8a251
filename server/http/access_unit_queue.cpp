#include "server/http/access_unit_queue.hpp"

#include <algorithm>

namespace labo::server {

AccessUnitQueue::AccessUnitQueue(std::size_t capacity) : ring_(std::max<std::size_t>(capacity, 1)) {}

AccessUnitQueue::PushResult AccessUnitQueue::push(const WireAccessUnit& unit) {
  PushResult result;
  if (count_ == ring_.size()) {
    result.dropped = count_;
    result.fell_behind = true;
    clear();
    waiting_for_keyframe_ = true;
  }
  if (waiting_for_keyframe_ && !unit.keyframe) {
    ++result.dropped;
    return result;
  }
  waiting_for_keyframe_ = false;
  ring_[(head_ + count_) % ring_.size()] = Entry{unit.geometry, unit.wire};
  bytes_ += (unit.geometry ? unit.geometry->size() : 0) + (unit.wire ? unit.wire->size() : 0);
  ++count_;
  result.queued = true;
  return result;
}

std::shared_ptr<const std::string> AccessUnitQueue::pop(bool& binary) {
  if (count_ == 0) return nullptr;
  Entry& e = ring_[head_];
  if (e.geometry) {
    binary = false;
    bytes_ -= e.geometry->size();
    return std::move(e.geometry);  // leaves e.geometry empty: the unit goes next
  }
  binary = true;
  auto wire = std::move(e.wire);
  if (wire) bytes_ -= wire->size();
  head_ = (head_ + 1) % ring_.size();
  --count_;
  return wire;
}

void AccessUnitQueue::clear() {
  for (std::size_t i = 0; i < count_; ++i) ring_[(head_ + i) % ring_.size()] = Entry{};
  head_ = count_ = bytes_ = 0;
}

void AccessUnitQueue::restart() {
  clear();
  waiting_for_keyframe_ = true;
}

}  // namespace labo::server
