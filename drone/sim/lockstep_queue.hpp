#pragma once
// What the lockstep links (SimDroneLink, SimTelloLink) share to carry their datagrams: a pool of
// reusable slots (a datagram's payload stays in its slot until delivered; steady state does not
// allocate) and a time-ordered queue of deliveries, ties delivered in the order scheduled.
#include <cstdint>
#include <functional>
#include <queue>
#include <vector>

#include "core/time.hpp"

namespace labo::sim {

template <typename T>
struct SlotPool {
  std::vector<T> items;
  std::vector<std::size_t> free;
  std::size_t acquire() {
    if (free.empty()) {
      items.emplace_back();
      return items.size() - 1;
    }
    const std::size_t i = free.back();
    free.pop_back();
    return i;
  }
  void release(std::size_t i) { free.push_back(i); }
};

template <typename Channel>
class DeliveryQueue {
 public:
  struct Delivery {
    Seconds t;
    std::uint64_t order;
    Channel channel;
    std::size_t slot;
    bool operator>(const Delivery& o) const { return t != o.t ? t > o.t : order > o.order; }
  };
  void schedule(Seconds t, Channel channel, std::size_t slot) { queue_.push({t, next_order_++, channel, slot}); }
  bool empty() const { return queue_.empty(); }
  const Delivery& top() const { return queue_.top(); }
  Delivery pop() {
    const Delivery d = queue_.top();
    queue_.pop();
    return d;
  }

 private:
  std::priority_queue<Delivery, std::vector<Delivery>, std::greater<>> queue_;
  std::uint64_t next_order_ = 0;
};

}  // namespace labo::sim
