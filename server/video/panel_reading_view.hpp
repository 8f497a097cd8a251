#pragma once
// The instrument reading view: while a panel is tracked, the panel rectified to its front view at
// its template's resolution, so that a student can read its display and labels. The homography from
// the template's rectangle to the tracked corners is applied, through the lens' distortion, to the
// very frame the corners were measured on (a short ring of recent frames, kept only while a panel
// is tracked), a few times per second, and the result goes out as a small JPEG: a 24-byte header
// like the JPEG path's with the magic "LDR1" (frame number and capture time of the rectified frame),
// then the JPEG. Undistorting matters: at 0.8 m a panel spans half the front camera's width, and a
// straight homography on the distorted image drops its similarity to the template from 0.94-0.96 to
// 0.81-0.91 (test "web: the reading view of the simulated lab at 0.8 m matches each panel's template").
#include <cstdint>
#include <memory>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "core/camera_model.hpp"
#include "drone/drone_link.hpp"
#include "server/video/overlay_model.hpp"
#include "server/video/wire_buffer_pool.hpp"

namespace labo::server {

// `corners` (tl, tr, br, bl: the panel's outer corners in `bgr`'s pixels) mapped onto a `size`
// image whose pixel centres sit half a pixel inside its edges, as the template's do, into `out`.
// With `camera`, the panel is a plane in the undistorted view and each output pixel is sampled
// through the lens' distortion (`map` is scratch space, reused).
void rectify_panel(const cv::Mat& bgr, const std::vector<cv::Point2f>& corners, cv::Size size,
                   const PinholeCamera* camera, cv::Mat& out, cv::Mat& map);

class PanelReadingView {
 public:
  // `front` is the front camera (its distortion is undone); frames of other cameras are taken as
  // undistorted.
  PanelReadingView(double rate_hz, int jpeg_quality, std::optional<PinholeCamera> front, std::size_t frames_kept = 8);

  // A new frame: kept (its pixels copied into a reused slot) while `panel` is tracked.
  void add_frame(const VideoFrame& frame, const OutlineOverlay& panel);
  // The reading view when one is due (at most `rate_hz` a second) and the frame the panel was
  // measured on is still kept; nullptr otherwise. `now` is the link clock's time.
  std::shared_ptr<const std::string> due(const OutlineOverlay& panel, Seconds now, double clock_to_unix_s);

 private:
  struct Kept {
    Seconds t = -1;
    std::uint32_t frame_number = 0;
    CameraId camera = CameraId::Front;
    cv::Mat bgr;
  };
  double period_s_;
  std::vector<int> jpeg_params_;
  std::optional<PinholeCamera> front_;
  std::vector<Kept> ring_;
  std::size_t next_ = 0;
  Seconds last_sent_ = -1e9;
  cv::Mat rectified_, map_;
  std::vector<std::uint8_t> jpeg_;
  WireBufferPool pool_;
};

}  // namespace labo::server
