#include "server/video/overlay_renderer.hpp"

#include <cmath>
#include <cstdio>
#include <opencv2/imgproc.hpp>

namespace labo::server {

namespace {

void draw_axes(cv::Mat& img, const AxesPx& a) {
  cv::arrowedLine(img, a.origin, a.x, {0, 0, 255}, 2, cv::LINE_AA, 0, 0.15);  // x red
  cv::arrowedLine(img, a.origin, a.y, {0, 200, 0}, 2, cv::LINE_AA, 0, 0.15);  // y green
  cv::arrowedLine(img, a.origin, a.z, {255, 80, 0}, 2, cv::LINE_AA, 0, 0.15);  // z blue
}

bool inside(const cv::Mat& img, const cv::Point2f& p) {
  return std::isfinite(p.x) && std::isfinite(p.y) && std::abs(p.x) < 4 * img.cols && std::abs(p.y) < 4 * img.rows;
}

}  // namespace

cv::Scalar bgr_of(const std::string& hex) {
  unsigned r = 0, g = 0, b = 0;
  if (hex.size() != 7 || hex[0] != '#' || std::sscanf(hex.c_str() + 1, "%02x%02x%02x", &r, &g, &b) != 3) return {0, 0, 0};
  return {static_cast<double>(b), static_cast<double>(g), static_cast<double>(r)};
}

void draw_overlays(cv::Mat& img, const OverlayModel& o, const FlightTelemetry& t) {
  if (img.empty()) return;
  const cv::Scalar source_colour = bgr_of(colour_of(t.source));
  for (const OutlineOverlay* outline : {&o.panel, &o.platform}) {
    const auto& c = outline->corners;
    if (c.size() == 4 && inside(img, c[0]))
      for (int i = 0; i < 4; ++i) cv::line(img, c[i], c[(i + 1) % 4], {255, 255, 0}, 2, cv::LINE_AA);
    if (outline->axes && inside(img, outline->axes->origin)) draw_axes(img, *outline->axes);
  }
  const FaceOverlay& face = o.face;
  const int n = static_cast<int>(face.points.size());
  for (const auto& [a, b] : face.edges)
    if (a >= 0 && b >= 0 && a < n && b < n) cv::line(img, face.points[a], face.points[b], {0, 220, 255}, 1, cv::LINE_AA);
  for (const auto& p : face.points)
    if (inside(img, p)) cv::circle(img, p, 2, {0, 160, 255}, cv::FILLED, cv::LINE_AA);
  if (face.axes && inside(img, face.axes->origin)) draw_axes(img, *face.axes);

  // Source colour as a frame border, so the state is visible at a glance.
  cv::rectangle(img, {0, 0, img.cols, img.rows}, source_colour, 6);
  // HUD: one strip along the top.
  cv::rectangle(img, {0, 0, img.cols, 22}, {0, 0, 0}, cv::FILLED);
  char hud[192];
  std::snprintf(hud, sizeof hud, "BAT %3.0f%%  ALT %4.2fm  YAW %+5.0fdeg  LINK %3.0f%%  %s %s  [%s]",
                t.battery_percent, t.altitude_m, t.pose.yaw_rad * 180.0 / M_PI, t.link_quality * 100.0,
                t.mission.c_str(), t.stage.c_str(), to_string(t.source).c_str());
  cv::putText(img, hud, {6, 16}, cv::FONT_HERSHEY_SIMPLEX, 0.45, {255, 255, 255}, 1, cv::LINE_AA);
  cv::circle(img, {img.cols - 14, 11}, 7, source_colour, cv::FILLED, cv::LINE_AA);
  cv::circle(img, {img.cols - 14, 11}, 7, {255, 255, 255}, 1, cv::LINE_AA);
}

}  // namespace labo::server
