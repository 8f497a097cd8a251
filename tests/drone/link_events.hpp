#pragma once
// A DroneLinkListener for the link tests: everything a link delivered, in order, thread-safe (live
// links call from their threads). Frames are kept as their facts; their pixels only when asked,
// as references (the receiver then cannot reuse its buffer: the replay tests rely on that).
#include <mutex>
#include <opencv2/core.hpp>
#include <utility>
#include <vector>

#include "drone/drone_link.hpp"

namespace labo::test {

struct FrameFacts {
  Seconds t = 0;
  std::uint32_t number = 0;
  CameraId camera = CameraId::Front;
  int width = 0, height = 0;
};

class LinkEvents : public DroneLinkListener {
 public:
  explicit LinkEvents(bool keep_pixels = false) : keep_pixels_(keep_pixels) {}

  void on_navdata(const NavdataSample& s) override {
    std::lock_guard l(m);
    navdata.push_back(s);
  }
  void on_video(const VideoFrame& f) override {
    std::lock_guard l(m);
    frames.push_back({f.t, f.frame_number, f.camera, f.bgr.cols, f.bgr.rows});
    if (keep_pixels_) pixels.push_back(f.bgr);
    last_pixels = f.bgr.clone();
  }
  void on_link_state(LinkState s, Seconds t) override {
    std::lock_guard l(m);
    states.emplace_back(s, t);
  }

  NavdataSample last() {
    std::lock_guard l(m);
    return navdata.empty() ? NavdataSample{} : navdata.back();
  }
  std::size_t frame_count() {
    std::lock_guard l(m);
    return frames.size();
  }
  FrameFacts last_frame() {
    std::lock_guard l(m);
    return frames.empty() ? FrameFacts{} : frames.back();
  }
  bool saw(LinkState s) {
    std::lock_guard l(m);
    for (const auto& [state, t] : states)
      if (state == s) return true;
    return false;
  }

  std::mutex m;  // guards everything below
  std::vector<NavdataSample> navdata;
  std::vector<FrameFacts> frames;
  std::vector<cv::Mat> pixels;  // with keep_pixels: each frame's, as delivered
  cv::Mat last_pixels;          // a copy of the last frame's
  std::vector<std::pair<LinkState, Seconds>> states;

 private:
  bool keep_pixels_;
};

}  // namespace labo::test
