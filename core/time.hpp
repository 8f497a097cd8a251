#pragma once
// Time in LaboDrone: every input carries a timestamp in seconds on the clock that produced it (the
// drone's, the simulator's or a recording's). Code under localization/ and control/ never reads the
// wall clock: it is handed timestamps, or a Clock, so that real time, lockstep simulation and replay
// give the same answers for the same inputs.
#include <chrono>

namespace labo {

// Seconds since the clock's own epoch (process start for SteadyClock, 0 for SimClock).
using Seconds = double;

class Clock {
 public:
  virtual ~Clock() = default;
  virtual Seconds now() const = 0;
};

// Monotonic wall time; used only by the real-time wrappers in drone/ and server/.
class SteadyClock final : public Clock {
 public:
  SteadyClock() : start_(std::chrono::steady_clock::now()) {}
  Seconds now() const override {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }

 private:
  std::chrono::steady_clock::time_point start_;
};

// A clock that moves only when told to: lockstep simulation and replay.
class SimClock final : public Clock {
 public:
  explicit SimClock(Seconds start = 0.0) : now_(start) {}
  Seconds now() const override { return now_; }
  void advance(Seconds dt) { now_ += dt; }
  void set(Seconds t) { now_ = t; }

 private:
  Seconds now_;
};

}  // namespace labo
