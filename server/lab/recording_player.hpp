#pragma once
// A flight recording played to the page while the lab goes on: the recording's own receivers decode it
// (ReplayLink, drone/replay/), each video frame is drawn with the recorded navdata beside it (time,
// altitude, battery, attitude, control state) and sent as an "LDP1" JPEG message
// (video/frame_header.hpp), apart from the live video. It plays at the pace it was recorded
// (`speed` times it) on its own thread; the live flight, its video and its clients are not touched.
// The frames go to whoever the caller's sinks choose (RemoteLab: the admin who asked, or everyone).
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include <opencv2/core.hpp>

#include "core/log.hpp"
#include "drone/drone_link.hpp"

namespace labo::replay {
class ReplayLink;
}  // namespace labo::replay

namespace labo::server {

// Draws one recorded frame with its navdata and encodes it as an LDP1 message. Not thread-safe: the
// player's thread owns it. Its buffers are reused from frame to frame.
class ReplayFrameEncoder final : public DroneLinkListener {
 public:
  using FrameSink = std::function<void(std::shared_ptr<const std::string> wire)>;
  // Frames wider than `max_width` are scaled down first (a replay is watched, not measured).
  ReplayFrameEncoder(FrameSink sink, int max_width = 640, int jpeg_quality = 75);

  void on_navdata(const NavdataSample& sample) override;
  void on_video(const VideoFrame& frame) override;
  void on_link_state(LinkState state, Seconds t) override;

  // The recording's time of its first record (set by the player); shown times count from it.
  void set_origin(Seconds t) { origin_ = t; }
  std::uint64_t frames() const { return frames_; }
  std::uint64_t navdata() const { return navdata_; }
  Seconds last_t() const { return last_t_; }

 private:
  void draw_navdata(cv::Mat& image, Seconds t) const;

  FrameSink sink_;
  int max_width_;
  std::vector<int> jpeg_params_;
  NavdataSample last_navdata_;
  bool have_navdata_ = false;
  LinkState link_ = LinkState::Disconnected;
  Seconds origin_ = 0;
  Seconds last_t_ = 0;
  std::uint64_t frames_ = 0, navdata_ = 0;
  cv::Mat scaled_;
  std::vector<std::uint8_t> jpeg_;
};

enum class ReplayState { Playing, Ended, Stopped, Failed };
std::string to_string(ReplayState state);

struct ReplayProgress {
  ReplayState state = ReplayState::Playing;
  double position_s = 0;  // recording time played, from its first record
  std::uint64_t frames = 0;
  std::uint64_t navdata = 0;
  std::string error;  // Failed: why (an unreadable or corrupt recording)
  bool truncated = false;  // the recording ends cut short (a crash during its flight)
};

class RecordingPlayer {
 public:
  using ProgressSink = std::function<void(const ReplayProgress& progress)>;
  // Opens the recording (throws replay::RecordingError when it is not one) and starts playing it.
  // `progress` is called at the start, about once a second while playing and once at the end (Ended, Stopped or
  // Failed), on the player's thread; neither sink may call back into the player.
  RecordingPlayer(const std::filesystem::path& file, double speed, ReplayFrameEncoder::FrameSink frames,
                  ProgressSink progress, Logger log);
  ~RecordingPlayer();  // stops and joins
  RecordingPlayer(const RecordingPlayer&) = delete;
  RecordingPlayer& operator=(const RecordingPlayer&) = delete;

  void stop();
  ReplayProgress progress() const;
  double speed() const { return speed_; }

 private:
  void run();
  void publish(ReplayState state, const std::string& error = {});

  double speed_;
  ProgressSink progress_sink_;
  Logger log_;
  std::unique_ptr<replay::ReplayLink> link_;
  ReplayFrameEncoder encoder_;
  mutable std::mutex mutex_;  // progress_, stop_
  std::condition_variable wake_;
  ReplayProgress progress_;
  bool stop_ = false;
  std::thread thread_;
};

}  // namespace labo::server
