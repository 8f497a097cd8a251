#pragma once
// For tests that fly over loopback in real time: wait for a condition, and point a driver at an
// emulator's ephemeral ports (test::link_settings_for, shared with the link's own loopback tests).
#include <chrono>
#include <thread>

#include "drone/ardrone2/ardrone_emulator.hpp"
#include "drone/ardrone2/ardrone_link.hpp"
#include "tests/drone/ardrone2/tiny_vehicle.hpp"

namespace labo::test {

// Polls `pred` every 10 ms for up to `timeout_s`; its last answer.
template <typename Pred>
bool eventually(Pred pred, double timeout_s) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  while (std::chrono::steady_clock::now() < end) {
    if (pred()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return pred();
}

}  // namespace labo::test
