#pragma once
// For tests that fly over loopback in real time: wait for a condition, and point a driver at an
// emulator's ephemeral ports.
#include <chrono>
#include <thread>

#include "drone/ardrone2/ardrone_emulator.hpp"
#include "drone/ardrone2/ardrone_link.hpp"

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

inline ArdroneLinkSettings driver_for(const ArdroneEmulator& emulator) {
  ArdroneLinkSettings s;
  s.host = "127.0.0.1";
  s.at_port = emulator.at_port();
  s.navdata_port = emulator.navdata_port();
  s.video_port = emulator.video_port();
  return s;
}

}  // namespace labo::test
