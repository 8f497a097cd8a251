#include "localization/planar/synthetic_scene.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include <opencv2/imgproc.hpp>

namespace labo {

cv::Mat make_procedural_panel(cv::Size size, std::uint32_t seed) {
  cv::RNG rng(seed);
  const int w = size.width, h = size.height;
  cv::Mat p(size, CV_8UC1, cv::Scalar(rng.uniform(150, 200)));
  const double u = std::min(w, h) / 100.0;  // layout unit
  cv::rectangle(p, cv::Rect(0, 0, w, h), cv::Scalar(40), std::max(1, static_cast<int>(2 * u)));
  // Display with a grid and a trace.
  const cv::Rect display(static_cast<int>(0.06 * w), static_cast<int>(0.08 * h), static_cast<int>(0.5 * w),
                         static_cast<int>(0.5 * h));
  cv::rectangle(p, display, cv::Scalar(30), cv::FILLED);
  for (int i = 1; i < 8; ++i) {
    const int x = display.x + i * display.width / 8;
    cv::line(p, {x, display.y}, {x, display.y + display.height}, cv::Scalar(70), 1);
  }
  for (int i = 1; i < 6; ++i) {
    const int y = display.y + i * display.height / 6;
    cv::line(p, {display.x, y}, {display.x + display.width, y}, cv::Scalar(70), 1);
  }
  const double freq = rng.uniform(2.0, 5.0), phase = rng.uniform(0.0, 6.28);
  cv::Point previous;
  for (int x = 0; x < display.width; ++x) {
    const double s = std::sin(freq * 6.283 * x / display.width + phase) + 0.3 * std::sin(13.0 * x / display.width);
    const cv::Point q(display.x + x, display.y + display.height / 2 - static_cast<int>(0.35 * display.height * s));
    if (x > 0) cv::line(p, previous, q, cv::Scalar(230), std::max(1, static_cast<int>(0.8 * u)), cv::LINE_AA);
    previous = q;
  }
  // Knobs on the right, buttons below the display, labels.
  for (int i = 0; i < 6; ++i) {
    const cv::Point c(static_cast<int>((0.66 + 0.16 * (i % 2)) * w), static_cast<int>((0.15 + 0.25 * (i / 2)) * h));
    const int r = static_cast<int>(rng.uniform(4.0, 7.0) * u);
    cv::circle(p, c, r, cv::Scalar(rng.uniform(20, 90)), cv::FILLED, cv::LINE_AA);
    const double a = rng.uniform(0.0, 6.28);
    cv::line(p, c, c + cv::Point(static_cast<int>(r * std::cos(a)), static_cast<int>(r * std::sin(a))),
             cv::Scalar(240), std::max(1, static_cast<int>(u)), cv::LINE_AA);
  }
  for (int i = 0; i < 7; ++i) {
    const cv::Rect b(static_cast<int>((0.06 + 0.075 * i) * w), static_cast<int>(0.68 * h), static_cast<int>(0.055 * w),
                     static_cast<int>(0.08 * h));
    cv::rectangle(p, b, cv::Scalar(rng.uniform(0, 2) ? 235 : 60), cv::FILLED);
    cv::rectangle(p, b, cv::Scalar(20), 1);
  }
  const char* labels[] = {"CH1", "CH2", "TRIG", "MEAS", "AUTO", "V/div", "s/div", "RUN"};
  for (int i = 0; i < 6; ++i) {
    const std::string text = labels[rng.uniform(0, 8)];
    cv::putText(p, text, cv::Point(static_cast<int>((0.06 + 0.15 * i) * w), static_cast<int>(0.9 * h)),
                cv::FONT_HERSHEY_SIMPLEX, 0.028 * u * 10, cv::Scalar(20), std::max(1, static_cast<int>(0.6 * u)),
                cv::LINE_AA);
  }
  for (const cv::Point c : {cv::Point(3, 3), cv::Point(w - 4, 3), cv::Point(3, h - 4), cv::Point(w - 4, h - 4)}) {
    cv::circle(p, c, std::max(1, static_cast<int>(1.5 * u)), cv::Scalar(90), cv::FILLED, cv::LINE_AA);
  }
  // A photo of a panel is band-limited (lens and sensor blur); hard one-pixel drawing edges would make
  // every sub-pixel resampling a visible change.
  cv::GaussianBlur(p, p, cv::Size(0, 0), 0.8);
  return p;
}

cv::Mat make_clutter_background(cv::Size size, std::uint32_t seed) {
  cv::RNG rng(seed);
  cv::Mat b(size, CV_8UC1, cv::Scalar(rng.uniform(90, 140)));
  const int n = size.area() / 1500;
  for (int i = 0; i < n; ++i) {
    const cv::Point c(rng.uniform(0, size.width), rng.uniform(0, size.height));
    const int r = rng.uniform(3, std::max(4, size.width / 12));
    const cv::Scalar g(rng.uniform(20, 236));
    if (rng.uniform(0, 2)) {
      cv::circle(b, c, r, g, cv::FILLED, cv::LINE_AA);
    } else {
      cv::rectangle(b, cv::Rect(c.x, c.y, r, rng.uniform(3, std::max(4, size.height / 10))), g, cv::FILLED);
    }
  }
  cv::GaussianBlur(b, b, cv::Size(3, 3), 0.8);
  cv::Mat noise(size, CV_16SC1), wide, out;
  rng.fill(noise, cv::RNG::NORMAL, 0, 4);
  b.convertTo(wide, CV_16S);
  wide += noise;
  wide.convertTo(out, CV_8U);  // saturates
  return out;
}

namespace {

// Area-averaged copy of the template, and the map from its pixels to the original's, when the
// template appears at `scale` < 1 (screen pixels per template pixel).
cv::Matx33d shrink(const cv::Mat& templ, double scale, cv::Mat& out) {
  if (scale >= 0.9) {
    out = templ;
    return cv::Matx33d::eye();
  }
  cv::resize(templ, out, cv::Size(), scale, scale, cv::INTER_AREA);
  const double sx = static_cast<double>(templ.cols) / out.cols, sy = static_cast<double>(templ.rows) / out.rows;
  return {sx, 0, 0.5 * sx - 0.5, 0, sy, 0.5 * sy - 0.5, 0, 0, 1};  // small px -> original px
}

// Writes `source` over `scene` where it lands, with anti-aliased panel edges: the panel is warped
// with replicated borders and blended through a warped coverage mask (so the outline sits exactly on
// the pixel edges of the template instead of being cut half a pixel inside).
template <typename Warp>
void blend_warped(const cv::Mat& source, cv::Mat& scene, Warp warp) {
  cv::Mat panel, coverage;
  warp(source, panel, cv::BORDER_REPLICATE, 0.0);
  // Coverage: 1 inside the panel, ramping to 0 over the half pixel outside its edge.
  cv::Mat ones(source.rows + 2, source.cols + 2, CV_32F, cv::Scalar(0));
  ones(cv::Rect(1, 1, source.cols, source.rows)).setTo(1.0);
  warp(ones, coverage, cv::BORDER_CONSTANT, 1.0);
  for (int y = 0; y < scene.rows; ++y) {
    uchar* s = scene.ptr<uchar>(y);
    const uchar* p = panel.ptr<uchar>(y);
    const float* c = coverage.ptr<float>(y);
    for (int x = 0; x < scene.cols; ++x) {
      const float a = std::clamp(c[x], 0.0f, 1.0f);
      s[x] = cv::saturate_cast<uchar>(a * p[x] + (1 - a) * s[x]);
    }
  }
}

}  // namespace

void draw_template(const cv::Mat& templ, const cv::Matx33d& H, cv::Mat& scene) {
  const double scale = std::sqrt(std::abs(cv::determinant(cv::Matx22d(H(0, 0), H(0, 1), H(1, 0), H(1, 1)))) /
                                 (H(2, 2) * H(2, 2)));
  cv::Mat small;
  const cv::Matx33d original_from_small = shrink(templ, scale, small);
  const cv::Matx33d M = H * original_from_small;
  blend_warped(small, scene, [&](const cv::Mat& src, cv::Mat& dst, int border, double offset) {
    // `offset` shifts the source by one pixel for the padded coverage image.
    const cv::Matx33d shift(1, 0, -offset, 0, 1, -offset, 0, 0, 1);
    cv::warpPerspective(src, dst, cv::Mat(M * shift), scene.size(), cv::INTER_LINEAR, border);
  });
}

cv::Mat render_planar_view(const cv::Mat& templ, double width_m, double height_m, const Eigen::Isometry3d& T_cam_object,
                           const PinholeCamera& camera, const cv::Mat& background) {
  const Eigen::Isometry3d T_object_cam = T_cam_object.inverse();
  const Eigen::Vector3d origin = T_object_cam.translation();
  // Apparent scale at the panel's centre, for anti-aliasing.
  const double depth = std::max(1e-3, T_cam_object.translation().z());
  const double scale = camera.intrinsics().fx * width_m / depth / templ.cols;
  cv::Mat small;
  const cv::Matx33d original_from_small = shrink(templ, scale, small);
  const cv::Matx33d small_from_original = original_from_small.inv();
  cv::Mat map(camera.height(), camera.width(), CV_32FC2);
  for (int y = 0; y < camera.height(); ++y) {
    auto* row = map.ptr<cv::Vec2f>(y);
    for (int x = 0; x < camera.width(); ++x) {
      const Eigen::Vector3d ray = T_object_cam.linear() * camera.unproject(Eigen::Vector2d(x, y));
      row[x] = cv::Vec2f(-1e6f, -1e6f);
      if (std::abs(ray.z()) < 1e-9) continue;
      const double s = -origin.z() / ray.z();
      if (s <= 0) continue;
      const Eigen::Vector3d p = origin + s * ray;
      const cv::Point2d u((p.x() / width_m + 0.5) * templ.cols - 0.5, (p.y() / height_m + 0.5) * templ.rows - 0.5);
      const cv::Vec3d q = small_from_original * cv::Vec3d(u.x, u.y, 1.0);
      row[x] = cv::Vec2f(static_cast<float>(q[0] / q[2]), static_cast<float>(q[1] / q[2]));
    }
  }
  cv::Mat out = background.clone();
  blend_warped(small, out, [&](const cv::Mat& src, cv::Mat& dst, int border, double offset) {
    cv::Mat shifted = map + cv::Scalar(offset, offset);
    cv::remap(src, dst, shifted, cv::noArray(), cv::INTER_LINEAR, border);
  });
  return out;
}

}  // namespace labo
