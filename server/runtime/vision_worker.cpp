#include "server/runtime/vision_worker.hpp"

#include <chrono>
#include <stdexcept>

namespace labo::server {

VisionWorker::VisionWorker(std::function<void()> on_done) : on_done_(std::move(on_done)), thread_([this] { loop(); }) {}

VisionWorker::~VisionWorker() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  cv_.notify_all();
  thread_.join();
}

bool VisionWorker::idle() const {
  std::lock_guard lock(mutex_);
  return state_ == State::Idle;
}

void VisionWorker::submit(fusion::VisionJob& job) {
  {
    std::lock_guard lock(mutex_);
    if (state_ != State::Idle) throw std::logic_error("VisionWorker::submit: the worker is busy");
    std::swap(job_, job);
    state_ = State::Running;
  }
  cv_.notify_all();
}

bool VisionWorker::take(fusion::VisionResults& out, double& run_ms) {
  std::lock_guard lock(mutex_);
  if (state_ != State::Done) return false;
  std::swap(out, results_);
  run_ms = run_ms_;
  state_ = State::Idle;
  return true;
}

void VisionWorker::loop() {
  std::unique_lock lock(mutex_);
  for (;;) {
    cv_.wait(lock, [this] { return stopping_ || state_ == State::Running; });
    if (stopping_) return;
    // The job and results belong to this thread while Running: the flight thread touches neither.
    lock.unlock();
    const auto start = std::chrono::steady_clock::now();
    try {
      fusion::run_vision_job(job_, results_);
    } catch (const std::exception& e) {
      // A front-end that throws must not take the server down: the frame yields nothing.
      results_.has_instrument = results_.has_platform = results_.has_face = results_.has_slam = false;
      results_.failure = e.what();
    }
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    lock.lock();
    run_ms_ = ms;
    state_ = State::Done;
    lock.unlock();
    if (on_done_) on_done_();
    lock.lock();
  }
}

}  // namespace labo::server
