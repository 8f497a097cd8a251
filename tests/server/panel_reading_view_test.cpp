#include <catch2/catch.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "drone/ardrone2/h264_codec.hpp"
#include "server/video/frame_header.hpp"
#include "server/video/panel_reading_view.hpp"
#include "tests/drone/sim/render_fixtures.hpp"

using namespace labo;
using namespace labo::lab;
using namespace labo::server;
using namespace labo::test;

namespace {

// Zero-mean normalized cross-correlation of two same-size images, in grey.
double ncc(const cv::Mat& a, const cv::Mat& b) {
  cv::Mat ga, gb, r;
  cv::cvtColor(a, ga, cv::COLOR_BGR2GRAY);
  cv::cvtColor(b, gb, cv::COLOR_BGR2GRAY);
  cv::matchTemplate(ga, gb, r, cv::TM_CCOEFF_NORMED);
  return r.at<float>(0, 0);
}

cv::Mat jpeg_of(const std::string& message) {
  const std::vector<std::uint8_t> bytes(message.begin() + FrameHeader::kSize, message.end());
  return cv::imdecode(bytes, cv::IMREAD_COLOR);
}

}  // namespace

TEST_CASE("web: the reading view rectifies the panel of the frame it was measured on, a few times a second") {
  // A textured template seen in perspective: frame n shows it shifted by 4n pixels.
  cv::Mat tpl(120, 200, CV_8UC3);
  cv::randu(tpl, 0, 255);
  cv::GaussianBlur(tpl, tpl, {0, 0}, 4.0);  // detail coarser than the two resamplings blur
  cv::normalize(tpl, tpl, 0, 255, cv::NORM_MINMAX);
  const std::vector<cv::Point2f> front{{-0.5f, -0.5f}, {199.5f, -0.5f}, {199.5f, 119.5f}, {-0.5f, 119.5f}};
  const auto corners_at = [](int n) {
    const float dx = 4.0f * static_cast<float>(n);
    return std::vector<cv::Point2f>{{150 + dx, 80}, {420 + dx, 100}, {410 + dx, 260}, {160 + dx, 250}};
  };
  PanelReadingView view(4.0, 90, std::nullopt, 4);
  OutlineOverlay panel;
  panel.template_px = tpl.size();
  for (int n = 0; n < 6; ++n) {
    VideoFrame f{0.1 * n, CameraId::Front, static_cast<std::uint32_t>(n), cv::Mat(360, 640, CV_8UC3, cv::Scalar(40, 40, 40))};
    cv::warpPerspective(tpl, f.bgr, cv::getPerspectiveTransform(front, corners_at(n)), f.bgr.size(), cv::INTER_LINEAR,
                        cv::BORDER_TRANSPARENT);
    panel.corners = corners_at(n);
    panel.measured_t = 0.1 * n;
    view.add_frame(f, panel);
  }
  // The tracker's newest result is for frame 3 (its latency: two frames behind): frame 3 is used.
  panel.corners = corners_at(3);
  panel.measured_t = 0.3;
  const auto message = view.due(panel, 0.5, 1000.0);
  REQUIRE(message);
  const auto header = FrameHeader::read(*message, "LDR1");
  REQUIRE(header);
  CHECK(header->frame_number == 3);
  CHECK(header->capture_unix_ms == Approx(1000300.0));
  const cv::Mat rectified = jpeg_of(*message);
  REQUIRE(rectified.size() == tpl.size());
  // Inside a band along the edges, where the synthetic frame's own warp blends into the background.
  const cv::Rect inner(8, 8, tpl.cols - 16, tpl.rows - 16);
  CHECK(ncc(rectified(inner).clone(), tpl(inner).clone()) > 0.98);
  // Not again before a quarter of a second, nor from a frame no longer kept (the ring holds 4).
  CHECK_FALSE(view.due(panel, 0.6, 1000.0));
  panel.measured_t = 0.1;
  CHECK_FALSE(view.due(panel, 0.8, 1000.0));
  // No template size, or no panel: nothing.
  panel.measured_t = 0.5;
  panel.template_px = {};
  CHECK_FALSE(view.due(panel, 0.9, 1000.0));
}

TEST_CASE("web: the reading view of the simulated lab at 0.8 m matches each panel's template (NCC >= 0.9)") {
  // The drone's view straight in front of each panel at 0.8 m, through the drone's H.264 at 4000
  // kbit/s, rectified with the panel's true corners (what a converged tracker reports).
  const LabDescription lab = load_lab_description(default_lab_path());
  LabRenderer renderer(lab, ardrone_cameras(), std::nullopt, 7);
  const PinholeCamera& camera = renderer.camera(CameraId::Front);
  int checked = 0;
  for (const InstrumentSpec& panel : lab.instruments) {
    const cv::Mat tpl = cv::imread(panel.template_path.string(), cv::IMREAD_COLOR);
    REQUIRE_FALSE(tpl.empty());
    const Eigen::Vector3d centre = panel.T_world_object.translation();
    const Eigen::Vector3d eye = centre - 0.8 * panel.T_world_object.linear().col(2);  // z points into the panel
    const SceneState scene = still_scene(body_looking_at(eye, centre));
    cv::Mat bgr;
    renderer.render(CameraId::Front, scene, bgr);
    ardrone2::H264Encoder encoder({.width = bgr.cols, .height = bgr.rows, .fps = 30, .gop = 15, .bitrate_kbps = 4000});
    ardrone2::H264Decoder decoder;
    ardrone2::EncodedFrame unit;
    cv::Mat decoded;
    for (int i = 0; i < 5; ++i) {  // the drone hovering: the same view, P frames after the IDR
      REQUIRE(encoder.encode(bgr, unit));
      decoder.decode(unit.data, decoded);
    }
    REQUIRE(decoded.size() == bgr.size());

    const Eigen::Isometry3d T_cam_world = (scene.T_world_body * T_body_cam_front()).inverse();
    std::vector<cv::Point2f> corners;
    for (const Eigen::Vector3d& c : panel.corners_world()) {
      const auto p = camera.project(T_cam_world * c);
      REQUIRE(p);
      REQUIRE(camera.in_image(*p, 0));
      corners.emplace_back(static_cast<float>(p->x()), static_cast<float>(p->y()));
    }
    cv::Mat rectified, map, straight;
    rectify_panel(decoded, corners, tpl.size(), &camera, rectified, map);
    const double similarity = ncc(rectified, tpl);
    // A straight homography, the lens ignored: the panel's middle bulges out of place.
    rectify_panel(decoded, corners, tpl.size(), nullptr, straight, map);
    INFO("without undoing the lens: NCC " << ncc(straight, tpl));
    CHECK(ncc(straight, tpl) < similarity);
    ++checked;
  }
  CHECK(checked >= 3);
}
