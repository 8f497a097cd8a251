#include "bench/soak/soak_audience.hpp"

#include <chrono>

namespace labo::bench {

SoakAudience::SoakAudience(boost::asio::io_context& io, unsigned short port, std::vector<std::string> cookies,
                           AudienceOptions options)
    : io_(io), port_(port), cookies_(std::move(cookies)), options_(options), random_(options.seed),
      thread_([this] { run(); }) {}

SoakAudience::~SoakAudience() { stop(); }

void SoakAudience::stop() {
  running_ = false;
  if (thread_.joinable()) thread_.join();
}

AudienceCounts SoakAudience::counts() const {
  AudienceCounts c;
  c.spectators_joined = joined_;
  c.slow_reader_stalls = stalls_;
  c.slow_reader_cut_off = cut_off_;
  c.connect_failures = failures_;
  c.frames_received = left_frames_;
  return c;
}

std::shared_ptr<SoakClient> SoakAudience::connect(bool small_buffer) {
  const std::string& cookie = cookies_[next_cookie_++ % cookies_.size()];
  try {
    return SoakClient::connect(io_, port_, cookie, small_buffer);
  } catch (const std::exception&) {
    ++failures_;  // counted, not fatal: the health probes say whether the server is up
    return nullptr;
  }
}

void SoakAudience::run() {
  const auto start = std::chrono::steady_clock::now();
  double next_join = 0;
  while (running_) {
    const double now = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    leave_due(now, false);
    if (now >= next_join) {
      next_join = now + options_.join_every_s;
      if (static_cast<int>(spectators_.size()) < options_.max_spectators) join(now);
    }
    drive_slow_reader(now);
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
  }
  leave_due(0, true);
  if (slow_) slow_->close();
}

void SoakAudience::join(double now_s) {
  auto client = connect(false);
  if (!client) return;
  ++joined_;
  // Every other spectator watches the drone's own H.264 stream; the others stay on JPEG.
  if (joined_ % 2 == 0) client->send({{"type", "subscribe"}, {"video", "h264"}});
  std::uniform_real_distribution<double> stay(options_.stay_min_s, options_.stay_max_s);
  spectators_.push_back({client, now_s + stay(random_)});
}

void SoakAudience::leave_due(double now_s, bool everyone) {
  for (auto it = spectators_.begin(); it != spectators_.end();) {
    if (everyone || now_s >= it->leave_at_s || !it->client->view().open) {
      left_frames_ += it->client->view().frames;
      it->client->close();
      it = spectators_.erase(it);
    } else {
      ++it;
    }
  }
}

void SoakAudience::drive_slow_reader(double now_s) {
  if (!slow_) {
    slow_ = connect(true);
    slow_stalled_ = false;
    slow_switch_at_s_ = now_s + options_.slow_read_s;
    return;
  }
  if (now_s < slow_switch_at_s_) return;
  if (!slow_stalled_) {
    slow_->pause_reading(true);
    ++stalls_;
    slow_stalled_ = true;
    slow_switch_at_s_ = now_s + options_.slow_stall_s;
    return;
  }
  // The stall is over: read again, and see whether the server kept it. A reader cut off comes back
  // with a new connection, as a page does.
  slow_->pause_reading(false);
  std::this_thread::sleep_for(std::chrono::milliseconds(500));  // drains what the buffers held
  if (!slow_->view().open) {
    ++cut_off_;
    slow_->close();
    slow_.reset();
    return;
  }
  slow_stalled_ = false;
  slow_switch_at_s_ = now_s + options_.slow_read_s;
}

}  // namespace labo::bench
