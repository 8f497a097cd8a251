#include "drone/sim/texture_procedural.hpp"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <stdexcept>
#include <string>

namespace labo::sim {

namespace {

struct Canvas {
  cv::Mat img;
  double px_per_m = 200;
  cv::RNG rng;

  int px(double metres) const { return static_cast<int>(std::lround(metres * px_per_m)); }
  double uniform(double a, double b) { return rng.uniform(a, b); }
  // Log-uniform: as many small things as large ones per octave, so corners exist at every distance.
  double log_uniform(double a, double b) { return std::exp(rng.uniform(std::log(a), std::log(b))); }
  cv::Point point() { return {rng.uniform(0, img.cols), rng.uniform(0, img.rows)}; }
};

cv::Scalar jitter(const cv::Scalar& base, double amount, cv::RNG& rng) {
  const double k = rng.uniform(-amount, amount);
  return {std::clamp(base[0] + k + rng.uniform(-8.0, 8.0), 0.0, 255.0), std::clamp(base[1] + k + rng.uniform(-8.0, 8.0), 0.0, 255.0),
          std::clamp(base[2] + k + rng.uniform(-8.0, 8.0), 0.0, 255.0)};
}

// Slow brightness variation (paint, dirt, light fall-off): a coarse random grid of gains,
// interpolated bilinearly over the texture.
void shade_slowly(Canvas& c, double amount) {
  const int gw = std::max(2, c.img.cols / 150), gh = std::max(2, c.img.rows / 150);
  std::vector<float> grid(static_cast<std::size_t>(gw * gh));
  for (float& g : grid) g = static_cast<float>(c.rng.uniform(1.0 - amount, 1.0 + amount));
  const float sx = static_cast<float>(gw - 1) / static_cast<float>(std::max(1, c.img.cols - 1));
  const float sy = static_cast<float>(gh - 1) / static_cast<float>(std::max(1, c.img.rows - 1));
  for (int y = 0; y < c.img.rows; ++y) {
    const float fy = static_cast<float>(y) * sy;
    const int y0 = std::min(static_cast<int>(fy), gh - 2);
    const float wy = fy - static_cast<float>(y0);
    auto* row = c.img.ptr<cv::Vec3b>(y);
    for (int x = 0; x < c.img.cols; ++x) {
      const float fx = static_cast<float>(x) * sx;
      const int x0 = std::min(static_cast<int>(fx), gw - 2);
      const float wx = fx - static_cast<float>(x0);
      const float* g0 = grid.data() + y0 * gw + x0;
      const float g = (g0[0] * (1 - wx) + g0[1] * wx) * (1 - wy) + (g0[gw] * (1 - wx) + g0[gw + 1] * wx) * wy;
      for (int k = 0; k < 3; ++k) row[x][k] = cv::saturate_cast<std::uint8_t>(row[x][k] * g);
    }
  }
}

// Small marks of every size between min_m and max_m: rectangles, triangles, strokes and dots.
void scatter_marks(Canvas& c, int count, double min_m, double max_m, const cv::Scalar& base, double contrast) {
  for (int i = 0; i < count; ++i) {
    const cv::Point p = c.point();
    const int s = std::max(1, c.px(c.log_uniform(min_m, max_m)));
    const cv::Scalar col = jitter(base, contrast, c.rng);
    switch (c.rng.uniform(0, 4)) {
      case 0:
        cv::rectangle(c.img, cv::Rect(p.x, p.y, s, std::max(1, c.rng.uniform(s / 3, s + 1))), col, cv::FILLED);
        break;
      case 1: {
        const cv::Point tri[3] = {p, p + cv::Point(s, c.rng.uniform(-s, s + 1)), p + cv::Point(c.rng.uniform(-s, s + 1), s)};
        cv::fillConvexPoly(c.img, tri, 3, col, cv::LINE_AA);
        break;
      }
      case 2:
        cv::line(c.img, p, p + cv::Point(c.rng.uniform(-2 * s, 2 * s + 1), c.rng.uniform(-s, s + 1)), col,
                 std::max(1, s / 5), cv::LINE_AA);
        break;
      default:
        cv::circle(c.img, p, std::max(1, s / 2), col, cv::FILLED, cv::LINE_AA);
        break;
    }
  }
}

std::string random_word(cv::RNG& rng) {
  static const char* kWords[] = {"LAB", "SAFETY", "OHM", "220V", "EXIT", "TP-3", "GND", "NOTE", "PCB", "RS-232",
                                 "LOG", "kHz", "mA", "ROOM B2", "ESD", "FUSE", "SCOPE", "DAQ", "5V", "V_OUT"};
  return kWords[rng.uniform(0, static_cast<int>(std::size(kWords)))];
}

// A notice board or poster: a frame, a title, lines of text and a small chart.
void poster(Canvas& c, cv::Rect r) {
  const cv::Scalar paper = jitter({225, 228, 232}, 25, c.rng);
  cv::rectangle(c.img, r, jitter({60, 60, 70}, 30, c.rng), cv::FILLED);
  const int border = std::max(2, r.width / 30);
  const cv::Rect inner(r.x + border, r.y + border, r.width - 2 * border, r.height - 2 * border);
  cv::rectangle(c.img, inner, paper, cv::FILLED);
  const double text_scale = std::max(0.3, inner.width / 260.0);
  const int line_h = std::max(6, static_cast<int>(26 * text_scale));
  for (int y = inner.y + line_h; y < inner.y + inner.height - 4; y += line_h) {
    if (c.rng.uniform(0, 5) == 0) {  // a chart instead of a text line
      std::vector<cv::Point> pts;
      for (int x = inner.x + 4; x < inner.x + inner.width - 4; x += std::max(2, inner.width / 20)) {
        pts.emplace_back(x, y - c.rng.uniform(0, line_h * 2));
      }
      cv::polylines(c.img, pts, false, jitter({150, 60, 40}, 60, c.rng), std::max(1, line_h / 8), cv::LINE_AA);
      y += line_h;
      continue;
    }
    std::string text = random_word(c.rng) + " " + random_word(c.rng) + " " + std::to_string(c.rng.uniform(10, 999));
    cv::putText(c.img, text, {inner.x + 4, y}, cv::FONT_HERSHEY_SIMPLEX, text_scale, jitter({40, 40, 40}, 30, c.rng),
                std::max(1, static_cast<int>(2 * text_scale)), cv::LINE_AA);
  }
  // Pins in the corners.
  for (const cv::Point& corner : {inner.tl(), cv::Point(inner.br().x, inner.y)}) {
    cv::circle(c.img, corner, std::max(2, border), jitter({40, 40, 200}, 40, c.rng), cv::FILLED, cv::LINE_AA);
  }
}

void draw_wall(Canvas& c, double width_m, double height_m) {
  static const cv::Scalar kPaints[] = {{205, 215, 222}, {190, 205, 200}, {215, 205, 195}, {200, 200, 205}};
  const cv::Scalar paint = kPaints[c.rng.uniform(0, 4)];
  c.img.setTo(paint);
  scatter_marks(c, static_cast<int>(width_m * height_m * 900), 0.004, 0.05, paint, 45);
  // Notice boards and posters at eye level.
  const int posters = static_cast<int>(width_m / 1.1) + 1;
  for (int i = 0; i < posters; ++i) {
    const double w = c.uniform(0.35, 1.1), h = c.uniform(0.3, 0.9);
    const double x = c.uniform(0.05, std::max(0.1, width_m - w - 0.05)), y = c.uniform(0.5, std::max(0.6, height_m - h - 1.1));
    poster(c, cv::Rect(c.px(x), c.px(y), c.px(w), c.px(h)));
  }
  // A cable duct 0.25 m above the floor, with sockets along it.
  const int duct_y = c.px(height_m - 0.30), duct_h = std::max(3, c.px(0.06));
  cv::rectangle(c.img, cv::Rect(0, duct_y, c.img.cols, duct_h), {232, 235, 236}, cv::FILLED);
  cv::line(c.img, {0, duct_y + duct_h / 2}, {c.img.cols, duct_y + duct_h / 2}, {200, 202, 204}, 1);
  for (double x = c.uniform(0.2, 0.8); x < width_m - 0.2; x += c.uniform(0.6, 1.6)) {
    const cv::Rect socket(c.px(x), duct_y - c.px(0.09), c.px(0.08), c.px(0.08));
    cv::rectangle(c.img, socket, {245, 245, 245}, cv::FILLED);
    cv::rectangle(c.img, socket, {120, 120, 120}, 1);
    cv::circle(c.img, socket.tl() + cv::Point(socket.width / 3, socket.height / 2), std::max(1, socket.width / 10), {30, 30, 30}, cv::FILLED);
    cv::circle(c.img, socket.tl() + cv::Point(2 * socket.width / 3, socket.height / 2), std::max(1, socket.width / 10), {30, 30, 30}, cv::FILLED);
  }
  // A skirting board.
  cv::rectangle(c.img, cv::Rect(0, c.px(height_m - 0.08), c.img.cols, c.px(0.08) + 1), {70, 80, 95}, cv::FILLED);
  shade_slowly(c, 0.06);
}

void draw_floor(Canvas& c, double width_m, double height_m) {
  const cv::Scalar base(150, 160, 165);
  c.img.setTo(base);
  // 0.5 m vinyl tiles, each its own shade, then scuffs and specks over everything.
  for (double y = 0; y < height_m; y += 0.5) {
    for (double x = 0; x < width_m; x += 0.5) {
      cv::rectangle(c.img, cv::Rect(c.px(x), c.px(y), c.px(0.5), c.px(0.5)), jitter(base, 22, c.rng), cv::FILLED);
    }
  }
  scatter_marks(c, static_cast<int>(width_m * height_m * 1400), 0.003, 0.06, base, 60);
  for (double y = 0; y < height_m; y += 0.5) cv::line(c.img, {0, c.px(y)}, {c.img.cols, c.px(y)}, {95, 100, 105}, 1);
  for (double x = 0; x < width_m; x += 0.5) cv::line(c.img, {c.px(x), 0}, {c.px(x), c.img.rows}, {95, 100, 105}, 1);
  shade_slowly(c, 0.08);
}

void draw_ceiling(Canvas& c, double width_m, double height_m) {
  const cv::Scalar base(225, 228, 228);
  c.img.setTo(base);
  scatter_marks(c, static_cast<int>(width_m * height_m * 200), 0.01, 0.05, base, 30);
  for (double y = 0; y < height_m; y += 0.6) cv::line(c.img, {0, c.px(y)}, {c.img.cols, c.px(y)}, {150, 150, 150}, 2);
  for (double x = 0; x < width_m; x += 0.6) cv::line(c.img, {c.px(x), 0}, {c.px(x), c.img.rows}, {150, 150, 150}, 2);
  for (double y = 0.6; y + 1.2 < height_m; y += 2.4) {
    for (double x = 0.6; x + 0.6 < width_m; x += 1.8) {
      cv::rectangle(c.img, cv::Rect(c.px(x), c.px(y), c.px(0.6), c.px(1.2)), {252, 252, 252}, cv::FILLED);
      cv::rectangle(c.img, cv::Rect(c.px(x), c.px(y), c.px(0.6), c.px(1.2)), {120, 120, 120}, 2);
    }
  }
}

void draw_bench_top(Canvas& c, double width_m, double height_m) {
  const cv::Scalar base(120, 150, 175);  // laminate
  c.img.setTo(base);
  scatter_marks(c, static_cast<int>(width_m * height_m * 1500), 0.003, 0.04, base, 50);
  // Things left on the bench: notes, a breadboard, tape, screws.
  const int items = static_cast<int>(width_m * height_m * 12) + 2;
  for (int i = 0; i < items; ++i) {
    const cv::Rect r(c.px(c.uniform(0, width_m - 0.2)), c.px(c.uniform(0, height_m - 0.15)), c.px(c.uniform(0.05, 0.2)),
                     c.px(c.uniform(0.04, 0.15)));
    cv::rectangle(c.img, r, jitter({200, 210, 215}, 60, c.rng), cv::FILLED);
    for (int k = 0; k < 6; ++k) {
      cv::circle(c.img, r.tl() + cv::Point(c.rng.uniform(0, r.width + 1), c.rng.uniform(0, r.height + 1)),
                 std::max(1, r.width / 15), jitter({40, 40, 40}, 30, c.rng), cv::FILLED);
    }
  }
  shade_slowly(c, 0.05);
}

void draw_bench_side(Canvas& c, double width_m, double height_m) {
  const cv::Scalar base(170, 175, 178);
  c.img.setTo(base);
  scatter_marks(c, static_cast<int>(width_m * height_m * 900), 0.004, 0.04, base, 40);
  // Cabinet doors with handles.
  for (double x = 0.02; x + 0.4 < width_m; x += 0.45) {
    const cv::Rect door(c.px(x), c.px(0.06), c.px(0.43), c.px(std::max(0.1, height_m - 0.16)));
    cv::rectangle(c.img, door, {110, 115, 118}, std::max(1, c.px(0.006)));
    cv::rectangle(c.img, cv::Rect(door.x + door.width - c.px(0.06), door.y + c.px(0.05), c.px(0.025), c.px(0.12)),
                  {60, 60, 60}, cv::FILLED);
  }
  shade_slowly(c, 0.05);
}

void draw_housing(Canvas& c, double width_m, double height_m) {
  const cv::Scalar base(70, 68, 66);
  c.img.setTo(base);
  scatter_marks(c, static_cast<int>(width_m * height_m * 3000), 0.002, 0.02, base, 30);
  // Ventilation slots.
  for (double y = 0.03; y + 0.01 < height_m; y += 0.02) {
    for (double x = 0.03; x + 0.06 < width_m; x += 0.08) {
      cv::rectangle(c.img, cv::Rect(c.px(x), c.px(y), c.px(0.05), std::max(1, c.px(0.006))), {25, 25, 25}, cv::FILLED);
    }
  }
}

void draw_platform_side(Canvas& c, double width_m, double height_m) {
  const cv::Scalar base(40, 140, 230);  // orange
  c.img.setTo(base);
  for (double x = 0; x < width_m; x += 0.1) {
    const cv::Point stripe[4] = {{c.px(x), 0}, {c.px(x + 0.05), 0}, {c.px(x + 0.05 - height_m), c.img.rows},
                                 {c.px(x - height_m), c.img.rows}};
    cv::fillConvexPoly(c.img, stripe, 4, {30, 30, 30}, cv::LINE_AA);
  }
  scatter_marks(c, static_cast<int>(width_m * height_m * 2000), 0.002, 0.01, base, 30);
}

}  // namespace

double metres_per_texel(SurfaceMaterial material) {
  switch (material) {
    case SurfaceMaterial::Wall:
    case SurfaceMaterial::Floor: return 0.005;
    case SurfaceMaterial::Ceiling: return 0.01;
    case SurfaceMaterial::BenchTop:
    case SurfaceMaterial::BenchSide: return 0.004;
    case SurfaceMaterial::Housing:
    case SurfaceMaterial::PlatformSide: return 0.002;
  }
  return 0.005;
}

cv::Mat draw_surface_texture(const SurfaceTextureRequest& q) {
  if (!(q.width_m > 0) || !(q.height_m > 0) || !(q.metres_per_texel > 0)) {
    throw std::invalid_argument("surface texture: sizes must be positive");
  }
  const int w = std::max(2, static_cast<int>(std::ceil(q.width_m / q.metres_per_texel)));
  const int h = std::max(2, static_cast<int>(std::ceil(q.height_m / q.metres_per_texel)));
  if (w > 4096 || h > 4096) {
    throw std::invalid_argument("surface texture: " + std::to_string(w) + "x" + std::to_string(h) +
                                " texels exceeds 4096 a side (surface too large for its texel size)");
  }
  Canvas c{cv::Mat(h, w, CV_8UC3), 1.0 / q.metres_per_texel, cv::RNG(0x9E3779B97F4A7C15ull ^ q.seed)};
  switch (q.material) {
    case SurfaceMaterial::Wall: draw_wall(c, q.width_m, q.height_m); break;
    case SurfaceMaterial::Floor: draw_floor(c, q.width_m, q.height_m); break;
    case SurfaceMaterial::Ceiling: draw_ceiling(c, q.width_m, q.height_m); break;
    case SurfaceMaterial::BenchTop: draw_bench_top(c, q.width_m, q.height_m); break;
    case SurfaceMaterial::BenchSide: draw_bench_side(c, q.width_m, q.height_m); break;
    case SurfaceMaterial::Housing: draw_housing(c, q.width_m, q.height_m); break;
    case SurfaceMaterial::PlatformSide: draw_platform_side(c, q.width_m, q.height_m); break;
  }
  // Bare areas: one flat colour, the surface's mean, so nothing inside them has a corner.
  const cv::Scalar flat = cv::mean(c.img);
  for (const auto& r : q.bare_m) {
    const cv::Rect px(c.px(r.x), c.px(r.y), c.px(r.width), c.px(r.height));
    cv::rectangle(c.img, px & cv::Rect(0, 0, w, h), flat, cv::FILLED);
  }
  return c.img;
}

}  // namespace labo::sim
