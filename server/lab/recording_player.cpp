#include "server/lab/recording_player.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "drone/replay/recording.hpp"
#include "drone/replay/replay_link.hpp"
#include "server/video/frame_header.hpp"

namespace labo::server {

namespace {

constexpr double kRadToDeg = 180.0 / M_PI;
constexpr double kProgressEveryS = 1.0;  // wall time between progress reports
constexpr double kMaxWaitS = 0.05;       // the longest sleep: a stop is seen this soon

const char* control_state_name(int state) {
  switch (state) {
    case 2: return "landed";
    case 3: return "flying";
    case 4: return "hovering";
    case 6: return "taking off";
    case 8: return "landing";
    default: return "other";
  }
}

void put_line(cv::Mat& image, const char* text, int row) {
  const cv::Point at(8, 18 + 18 * row);
  cv::putText(image, text, at, cv::FONT_HERSHEY_SIMPLEX, 0.45, cv::Scalar(0, 0, 0), 3, cv::LINE_AA);
  cv::putText(image, text, at, cv::FONT_HERSHEY_SIMPLEX, 0.45, cv::Scalar(255, 255, 255), 1, cv::LINE_AA);
}

}  // namespace

std::string to_string(ReplayState state) {
  switch (state) {
    case ReplayState::Playing: return "playing";
    case ReplayState::Ended: return "ended";
    case ReplayState::Stopped: return "stopped";
    case ReplayState::Failed: return "failed";
  }
  return "unknown";
}

// ---- ReplayFrameEncoder ------------------------------------------------------------------------

ReplayFrameEncoder::ReplayFrameEncoder(FrameSink sink, int max_width, int jpeg_quality)
    : sink_(std::move(sink)), max_width_(max_width), jpeg_params_{cv::IMWRITE_JPEG_QUALITY, jpeg_quality} {}

void ReplayFrameEncoder::on_navdata(const NavdataSample& sample) {
  last_navdata_ = sample;
  have_navdata_ = true;
  last_t_ = sample.t;
  ++navdata_;
}

void ReplayFrameEncoder::on_link_state(LinkState state, Seconds t) {
  link_ = state;
  last_t_ = t;
}

void ReplayFrameEncoder::on_video(const VideoFrame& frame) {
  if (frame.bgr.empty()) return;
  last_t_ = frame.t;
  if (frame.bgr.cols > max_width_) {
    const double s = static_cast<double>(max_width_) / frame.bgr.cols;
    cv::resize(frame.bgr, scaled_, cv::Size(max_width_, static_cast<int>(std::lround(frame.bgr.rows * s))), 0, 0,
               cv::INTER_AREA);
  } else {
    frame.bgr.copyTo(scaled_);  // drawn on: the decoder's buffer stays as it is
  }
  draw_navdata(scaled_, frame.t);
  cv::imencode(".jpg", scaled_, jpeg_, jpeg_params_);
  FrameHeader h;
  h.frame_number = frame.frame_number;
  h.capture_unix_ms = (frame.t - origin_) * 1000.0;  // LDP1: the recording's time, not the epoch
  h.camera = static_cast<std::uint8_t>(frame.camera);
  h.jpeg_bytes = static_cast<std::uint32_t>(jpeg_.size());
  auto wire = std::make_shared<std::string>(FrameHeader::kSize + jpeg_.size(), '\0');
  h.write(wire->data(), "LDP1");
  std::copy(jpeg_.begin(), jpeg_.end(), wire->begin() + FrameHeader::kSize);
  ++frames_;
  sink_(std::move(wire));
}

void ReplayFrameEncoder::draw_navdata(cv::Mat& image, Seconds t) const {
  char line[128];
  std::snprintf(line, sizeof line, "REPLAY  t %.1f s  link %s", t - origin_, to_string(link_).c_str());
  put_line(image, line, 0);
  if (!have_navdata_) return;
  const NavdataSample& n = last_navdata_;
  std::snprintf(line, sizeof line, "alt %.2f m  battery %.0f %%  %s", n.altitude_m, n.battery_percent,
                control_state_name(n.control_state));
  put_line(image, line, 1);
  std::snprintf(line, sizeof line, "roll %.1f  pitch %.1f  yaw %.1f deg", n.roll_rad * kRadToDeg, n.pitch_rad * kRadToDeg,
                n.yaw_rad * kRadToDeg);
  put_line(image, line, 2);
}

// ---- RecordingPlayer ---------------------------------------------------------------------------

RecordingPlayer::RecordingPlayer(const std::filesystem::path& file, double speed, ReplayFrameEncoder::FrameSink frames,
                                 ProgressSink progress, Logger log)
    : speed_(speed),
      progress_sink_(std::move(progress)),
      log_(std::move(log)),
      link_(std::make_unique<replay::ReplayLink>(file, log_.child("replay"))),
      encoder_(std::move(frames)) {
  link_->set_listener(&encoder_);
  thread_ = std::thread([this] { run(); });
}

RecordingPlayer::~RecordingPlayer() {
  stop();
  if (thread_.joinable()) thread_.join();
}

void RecordingPlayer::stop() {
  std::lock_guard lock(mutex_);
  stop_ = true;
  wake_.notify_all();
}

ReplayProgress RecordingPlayer::progress() const {
  std::lock_guard lock(mutex_);
  return progress_;
}

void RecordingPlayer::publish(ReplayState state, const std::string& error) {
  ReplayProgress p;
  p.state = state;
  p.frames = encoder_.frames();
  p.navdata = encoder_.navdata();
  p.error = error;
  p.truncated = link_->truncated();
  {
    std::lock_guard lock(mutex_);
    p.position_s = progress_.position_s;
    progress_ = p;
  }
  if (progress_sink_) progress_sink_(p);
}

void RecordingPlayer::run() {
  using SteadyClock = std::chrono::steady_clock;
  try {
    const Seconds origin = link_->next_time();
    encoder_.set_origin(std::isfinite(origin) ? origin : 0.0);
    publish(ReplayState::Playing);  // from here, so that it comes before the frames and the end
    const auto start = SteadyClock::now();
    auto last_report = start;
    for (;;) {
      const double elapsed_s = std::chrono::duration<double>(SteadyClock::now() - start).count();
      const Seconds target = origin + elapsed_s * speed_;
      const bool more = std::isfinite(origin) && link_->advance_to(target);
      {
        std::lock_guard lock(mutex_);
        progress_.position_s = std::max(0.0, (more ? target : encoder_.last_t()) - origin);
      }
      if (!more) {
        publish(ReplayState::Ended);
        return;
      }
      const auto now = SteadyClock::now();
      if (std::chrono::duration<double>(now - last_report).count() >= kProgressEveryS) {
        last_report = now;
        publish(ReplayState::Playing);
      }
      const double wait_s = std::clamp((link_->next_time() - target) / speed_, 0.0, kMaxWaitS);
      std::unique_lock lock(mutex_);
      if (wake_.wait_for(lock, std::chrono::duration<double>(wait_s), [this] { return stop_; })) {
        lock.unlock();
        publish(ReplayState::Stopped);
        return;
      }
    }
  } catch (const std::exception& e) {
    log_.warn(encoder_.last_t(), "replay failed").kv("error", e.what());
    publish(ReplayState::Failed, e.what());
  }
}

}  // namespace labo::server
