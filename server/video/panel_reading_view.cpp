#include "server/video/panel_reading_view.hpp"

#include <cmath>
#include <cstring>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "server/video/frame_header.hpp"

namespace labo::server {

void rectify_panel(const cv::Mat& bgr, const std::vector<cv::Point2f>& corners, cv::Size size,
                   const PinholeCamera* camera, cv::Mat& out, cv::Mat& map) {
  const float w = static_cast<float>(size.width), h = static_cast<float>(size.height);
  const std::vector<cv::Point2f> front{{-0.5f, -0.5f}, {w - 0.5f, -0.5f}, {w - 0.5f, h - 0.5f}, {-0.5f, h - 0.5f}};
  if (!camera || !camera->has_distortion()) {
    const cv::Mat H = cv::getPerspectiveTransform(corners, front);
    cv::warpPerspective(bgr, out, H, size, cv::INTER_LINEAR, cv::BORDER_CONSTANT, cv::Scalar(0, 0, 0));
    return;
  }
  // The corners in undistorted normalized coordinates; the template's rectangle onto them; each
  // template pixel back through the distortion to the frame's pixel it is sampled from.
  const CameraIntrinsics& k = camera->intrinsics();
  std::vector<cv::Point2f> plane(4);
  for (int i = 0; i < 4; ++i) {
    const Eigen::Vector2d n = camera->undistort({(corners[i].x - k.cx) / k.fx, (corners[i].y - k.cy) / k.fy});
    plane[i] = {static_cast<float>(n.x()), static_cast<float>(n.y())};
  }
  const cv::Matx33d H(cv::getPerspectiveTransform(front, plane));
  map.create(size, CV_32FC2);
  for (int y = 0; y < size.height; ++y) {
    auto* row = map.ptr<cv::Vec2f>(y);
    for (int x = 0; x < size.width; ++x) {
      const cv::Vec3d p = H * cv::Vec3d(x, y, 1.0);
      const Eigen::Vector2d d = camera->distort({p[0] / p[2], p[1] / p[2]});
      row[x] = {static_cast<float>(k.fx * d.x() + k.cx), static_cast<float>(k.fy * d.y() + k.cy)};
    }
  }
  cv::remap(bgr, out, map, cv::noArray(), cv::INTER_LINEAR, cv::BORDER_CONSTANT, cv::Scalar(0, 0, 0));
}

PanelReadingView::PanelReadingView(double rate_hz, int jpeg_quality, std::optional<PinholeCamera> front,
                                   std::size_t frames_kept)
    : period_s_(rate_hz > 0 ? 1.0 / rate_hz : 1e9),
      jpeg_params_{cv::IMWRITE_JPEG_QUALITY, jpeg_quality},
      front_(std::move(front)),
      ring_(std::max<std::size_t>(frames_kept, 1)),
      pool_(4, 128 * 1024) {}

void PanelReadingView::add_frame(const VideoFrame& frame, const OutlineOverlay& panel) {
  if (panel.corners.size() != 4 || panel.template_px.empty()) return;
  Kept& slot = ring_[next_];
  next_ = (next_ + 1) % ring_.size();
  slot.t = frame.t;
  slot.frame_number = frame.frame_number;
  slot.camera = frame.camera;
  frame.bgr.copyTo(slot.bgr);  // reuses the slot's buffer once it has the frame's size
}

std::shared_ptr<const std::string> PanelReadingView::due(const OutlineOverlay& panel, Seconds now, double clock_to_unix_s) {
  if (panel.corners.size() != 4 || panel.template_px.empty() || now - last_sent_ < period_s_) return nullptr;
  const Kept* measured = nullptr;
  for (const Kept& k : ring_)
    if (k.t >= 0 && std::abs(k.t - panel.measured_t) < 1e-6) measured = &k;
  if (!measured) return nullptr;  // that frame is gone (vision slower than the ring): the next one
  last_sent_ = now;
  const PinholeCamera* lens = measured->camera == CameraId::Front && front_ ? &*front_ : nullptr;
  rectify_panel(measured->bgr, panel.corners, panel.template_px, lens, rectified_, map_);
  cv::imencode(".jpg", rectified_, jpeg_, jpeg_params_);
  auto buffer = pool_.acquire();
  buffer->resize(FrameHeader::kSize + jpeg_.size());
  FrameHeader{measured->frame_number, (measured->t + clock_to_unix_s) * 1000.0, 0, static_cast<std::uint32_t>(jpeg_.size())}
      .write(buffer->data(), "LDR1");
  std::memcpy(buffer->data() + FrameHeader::kSize, jpeg_.data(), jpeg_.size());
  return buffer;
}

}  // namespace labo::server
