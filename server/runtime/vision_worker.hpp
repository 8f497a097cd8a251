#pragma once
// The flight software's vision on a thread of its own, so that control keeps ticking while a frame
// is detected or tracked (a template search or SIFT costs several control periods). One job at a
// time: the flight thread prepares a job only while the worker is idle and keeps just the newest
// frame meanwhile, so a slow detection drops frames instead of queueing them. Jobs and results are
// swapped in and out, never copied: steady operation allocates nothing.
#include <condition_variable>
#include <functional>
#include <mutex>
#include <thread>

#include "localization/fusion/vision_job.hpp"

namespace labo::server {

class VisionWorker {
 public:
  // `on_done` is called on the worker's thread when a job's results are ready (to wake the flight
  // thread); it must not call back into the worker.
  explicit VisionWorker(std::function<void()> on_done);
  ~VisionWorker();
  VisionWorker(const VisionWorker&) = delete;
  VisionWorker& operator=(const VisionWorker&) = delete;

  // No job running and no results waiting to be taken.
  bool idle() const;
  // Starts `job` (requires idle()); the caller gets the worker's previous job buffers back in `job`.
  void submit(fusion::VisionJob& job);
  // The finished job's results swapped into `out`, with the time the front-ends took (steady
  // clock, ms); false when none is ready.
  bool take(fusion::VisionResults& out, double& run_ms);

 private:
  enum class State { Idle, Running, Done };
  void loop();

  std::function<void()> on_done_;
  mutable std::mutex mutex_;
  std::condition_variable cv_;
  State state_ = State::Idle;
  bool stopping_ = false;
  fusion::VisionJob job_;
  fusion::VisionResults results_;
  double run_ms_ = 0;
  std::thread thread_;  // last: started once the members above exist
};

}  // namespace labo::server
