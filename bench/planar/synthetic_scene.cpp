#include "bench/planar/synthetic_scene.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include <opencv2/imgproc.hpp>

namespace labo::bench {

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
  // An explicit size: with scale factors OpenCV maps pixels by the factor, not by the size ratio.
  const cv::Size size(std::max(1, static_cast<int>(std::lround(templ.cols * scale))),
                      std::max(1, static_cast<int>(std::lround(templ.rows * scale))));
  cv::resize(templ, out, size, 0, 0, cv::INTER_AREA);
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

PlanarViewRenderer::PlanarViewRenderer(const PinholeCamera& camera, cv::Mat wall, double wall_m_per_px,
                                       double wall_depth_m)
    : camera_(camera), wall_(std::move(wall)), wall_m_per_px_(wall_m_per_px), wall_depth_m_(wall_depth_m) {
  rays_.reserve(static_cast<std::size_t>(camera.width() * camera.height()));
  for (int y = 0; y < camera.height(); ++y) {
    for (int x = 0; x < camera.width(); ++x) rays_.push_back(camera.unproject(Eigen::Vector2d(x, y)).cast<float>());
  }
}

namespace {

// The integral of the template over [0, x) x [0, y) (template px, texel edges at integers) from its
// summed-area table: bilinear within a texel, exact for piecewise-constant texels.
double area_integral(const cv::Mat& sat, double x, double y) {
  const int w = sat.cols - 1, h = sat.rows - 1;
  x = std::clamp(x, 0.0, static_cast<double>(w));
  y = std::clamp(y, 0.0, static_cast<double>(h));
  const int i = std::min(static_cast<int>(x), w - 1), j = std::min(static_cast<int>(y), h - 1);
  const double fx = x - i, fy = y - j;
  const double* r0 = sat.ptr<double>(j);
  const double* r1 = sat.ptr<double>(j + 1);
  const double top = r0[i] + fx * (r0[i + 1] - r0[i]), bottom = r1[i] + fx * (r1[i + 1] - r1[i]);
  return top + fy * (bottom - top);
}

}  // namespace

cv::Mat PlanarViewRenderer::render(const cv::Mat& templ, double width_m, double height_m,
                                   const Eigen::Isometry3d& T_cam_object) const {
  const Eigen::Isometry3d T_object_cam = T_cam_object.inverse();
  const Eigen::Matrix3f R = T_object_cam.linear().cast<float>();
  const Eigen::Vector3f origin = T_object_cam.translation().cast<float>();
  // Where each pixel's centre meets the panel's plane, in template px (texel edges at integers).
  cv::Mat panel_map(camera_.height(), camera_.width(), CV_32FC2), wall_map(camera_.height(), camera_.width(), CV_32FC2);
  constexpr float kNone = -1e6f;
  std::size_t k = 0;
  for (int y = 0; y < camera_.height(); ++y) {
    auto* prow = panel_map.ptr<cv::Vec2f>(y);
    auto* wrow = wall_map.ptr<cv::Vec2f>(y);
    for (int x = 0; x < camera_.width(); ++x, ++k) {
      const Eigen::Vector3f ray = R * rays_[k];
      prow[x] = wrow[x] = cv::Vec2f(kNone, kNone);
      if (ray.z() <= 1e-6f) continue;  // parallel to or away from the planes
      const float s_panel = -origin.z() / ray.z();
      if (s_panel > 0) {
        const Eigen::Vector3f p = origin + s_panel * ray;
        prow[x] = cv::Vec2f(static_cast<float>((p.x() / width_m + 0.5) * templ.cols),
                            static_cast<float>((p.y() / height_m + 0.5) * templ.rows));
      }
      const float s_wall = (static_cast<float>(wall_depth_m_) - origin.z()) / ray.z();
      if (s_wall > 0 && !wall_.empty()) {
        const Eigen::Vector3f p = origin + s_wall * ray;
        wrow[x] = cv::Vec2f(static_cast<float>(p.x() / wall_m_per_px_ + wall_.cols / 2.0),
                            static_cast<float>(p.y() / wall_m_per_px_ + wall_.rows / 2.0));
      }
    }
  }
  cv::Mat out(camera_.height(), camera_.width(), CV_8UC1, cv::Scalar(120));
  if (!wall_.empty()) cv::remap(wall_, out, wall_map, cv::noArray(), cv::INTER_LINEAR, cv::BORDER_WRAP);
  // Each pixel records the panel's mean over the pixel's footprint, as a camera's pixel integrates the
  // light over its area (the template's texels piecewise constant): the pixel square mapped onto the
  // template by the local Jacobian of the map, split into 2 x 2 sub-squares, each a box with its second
  // moments along the template's axes (a sheared or rotated footprint is then close to its true shape),
  // each box's mean read from the summed-area table. The part of the footprint outside the panel shows
  // the wall: the pixel blends the two by the covered area. Why not shrink the template to the
  // panel's size and sample it bilinearly: resampled twice, each pixel's kernel would depend on its
  // sub-pixel phase and displace the detail by a fraction of a pixel, which reads as a tilt of a
  // degree at 2-3 m.
  cv::Mat sat;
  cv::integral(templ, sat, CV_64F);
  const double tw = templ.cols, th = templ.rows;
  const auto at = [&](int x, int y) { return panel_map.at<cv::Vec2f>(y, x); };
  const auto valid = [&](int x, int y) {
    return x >= 0 && y >= 0 && x < panel_map.cols && y < panel_map.rows && at(x, y)[0] > kNone / 2;
  };
  // The map's derivative along one image axis at (x, y): central where both neighbours hit the plane.
  const auto derivative = [&](int x, int y, int dx, int dy, cv::Vec2f& d) {
    const bool ahead = valid(x + dx, y + dy), behind = valid(x - dx, y - dy);
    if (ahead && behind) {
      d = 0.5f * (at(x + dx, y + dy) - at(x - dx, y - dy));
    } else if (ahead) {
      d = at(x + dx, y + dy) - at(x, y);
    } else if (behind) {
      d = at(x, y) - at(x - dx, y - dy);
    } else {
      return false;
    }
    return true;
  };
  for (int y = 0; y < out.rows; ++y) {
    uchar* o = out.ptr<uchar>(y);
    for (int x = 0; x < out.cols; ++x) {
      if (!valid(x, y)) continue;
      const cv::Vec2f c = at(x, y);
      cv::Vec2f du, dv;  // template px per image px along x and along y
      if (!derivative(x, y, 1, 0, du) || !derivative(x, y, 0, 1, dv)) continue;
      const double reach_u = 0.5 * (std::abs(du[0]) + std::abs(dv[0])), reach_v = 0.5 * (std::abs(du[1]) + std::abs(dv[1]));
      if (c[0] + reach_u <= 0 || c[1] + reach_v <= 0 || c[0] - reach_u >= tw || c[1] - reach_v >= th) continue;
      // A quarter pixel's square: half-sizes from the rows of the Jacobian (second moments).
      const double hu = 0.25 * std::hypot(du[0], dv[0]), hv = 0.25 * std::hypot(du[1], dv[1]);
      if (!(hu > 0 && hv > 0)) continue;
      double inside = 0, integral = 0;
      for (const float sy : {-0.25f, 0.25f}) {
        for (const float sx : {-0.25f, 0.25f}) {
          const cv::Vec2f q = c + sx * du + sy * dv;
          const double u0 = std::max(0.0, q[0] - hu), u1 = std::min(tw, q[0] + hu);
          const double v0 = std::max(0.0, q[1] - hv), v1 = std::min(th, q[1] + hv);
          if (!(u1 > u0 && v1 > v0)) continue;
          inside += (u1 - u0) * (v1 - v0);
          integral += area_integral(sat, u1, v1) - area_integral(sat, u0, v1) - area_integral(sat, u1, v0) + area_integral(sat, u0, v0);
        }
      }
      const double footprint = 4.0 * (2 * hu) * (2 * hv);
      const double covered = std::min(1.0, inside / footprint);
      o[x] = cv::saturate_cast<uchar>(integral / footprint + (1.0 - covered) * o[x]);
    }
  }
  return out;
}

Eigen::Isometry3d look_at_object(const Eigen::Vector3d& camera_in_object, const Eigen::Vector3d& target, double roll_rad) {
  const Eigen::Vector3d z = (target - camera_in_object).normalized();
  Eigen::Vector3d x = Eigen::Vector3d::UnitY().cross(z);
  if (x.norm() < 1e-6) x = Eigen::Vector3d::UnitX();
  x.normalize();
  const Eigen::Vector3d y = z.cross(x);
  Eigen::Matrix3d R;
  R << x, y, z;
  Eigen::Isometry3d T_object_cam = Eigen::Isometry3d::Identity();
  T_object_cam.linear() = R * Eigen::AngleAxisd(roll_rad, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  T_object_cam.translation() = camera_in_object;
  return T_object_cam.inverse();
}

}  // namespace labo::bench
