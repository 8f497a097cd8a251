#include "drone/lab/instrument_panels.hpp"

#include <cmath>
#include <numbers>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

namespace labo::lab {

namespace {

const cv::Scalar kPanelGrey(178, 174, 170);
const cv::Scalar kDark(40, 38, 36);
const cv::Scalar kScreen(40, 60, 30);

void label(cv::Mat& img, const std::string& text, cv::Point at, double scale, const cv::Scalar& colour, int thick = 1) {
  cv::putText(img, text, at, cv::FONT_HERSHEY_SIMPLEX, scale, colour, thick, cv::LINE_AA);
}

// A knob with a pointer at `angle_deg` and tick marks around it.
void knob(cv::Mat& img, cv::Point c, int r, double angle_deg, const cv::Scalar& body) {
  for (int k = 0; k <= 10; ++k) {
    const double a = (-225 + 27 * k) * std::numbers::pi / 180.0;
    cv::line(img, c + cv::Point(int((r + 4) * std::cos(a)), int((r + 4) * std::sin(a))),
             c + cv::Point(int((r + 10) * std::cos(a)), int((r + 10) * std::sin(a))), kDark, 1, cv::LINE_AA);
  }
  cv::circle(img, c, r, kDark, cv::FILLED, cv::LINE_AA);
  cv::circle(img, c, r - 3, body, cv::FILLED, cv::LINE_AA);
  const double a = angle_deg * std::numbers::pi / 180.0;
  cv::line(img, c, c + cv::Point(int((r - 4) * std::cos(a)), int((r - 4) * std::sin(a))), cv::Scalar(250, 250, 250), 3,
           cv::LINE_AA);
}

void button(cv::Mat& img, cv::Rect r, const cv::Scalar& colour, const std::string& text) {
  cv::rectangle(img, r, kDark, cv::FILLED);
  cv::rectangle(img, {r.x + 2, r.y + 2, r.width - 4, r.height - 4}, colour, cv::FILLED);
  label(img, text, {r.x + 4, r.y + r.height + 14}, 0.38, kDark);
}

// A display: background, graticule, a waveform y = f(x) in [-1, 1], and a readout.
template <typename F>
void scope_display(cv::Mat& img, cv::Rect r, F f, const cv::Scalar& trace, const std::string& readout) {
  cv::rectangle(img, r, kDark, 4);
  cv::rectangle(img, r, kScreen, cv::FILLED);
  for (int i = 1; i < 10; ++i) cv::line(img, {r.x + r.width * i / 10, r.y}, {r.x + r.width * i / 10, r.y + r.height}, {70, 90, 60}, 1);
  for (int i = 1; i < 8; ++i) cv::line(img, {r.x, r.y + r.height * i / 8}, {r.x + r.width, r.y + r.height * i / 8}, {70, 90, 60}, 1);
  std::vector<cv::Point> pts;
  for (int x = 0; x < r.width; x += 2) {
    const double v = f(static_cast<double>(x) / r.width);
    pts.emplace_back(r.x + x, r.y + int(r.height * (0.5 - 0.42 * v)));
  }
  cv::polylines(img, pts, false, trace, 2, cv::LINE_AA);
  label(img, readout, {r.x + 8, r.y + 22}, 0.55, {200, 230, 200}, 1);
}

// Seven-segment-like digits on a dark display.
void digit_display(cv::Mat& img, cv::Rect r, const std::string& digits, const cv::Scalar& colour) {
  cv::rectangle(img, r, kDark, cv::FILLED);
  const double scale = r.height / 34.0;
  label(img, digits, {r.x + 8, r.y + r.height - int(6 * scale)}, scale, colour, std::max(2, int(2 * scale)));
}

}  // namespace

cv::Mat draw_oscilloscope_panel() {
  cv::Mat img(400, 800, CV_8UC3, kPanelGrey);
  cv::rectangle(img, {0, 0, 800, 400}, kDark, 10);
  scope_display(img, {30, 40, 440, 300},
                [](double x) { return 0.8 * std::sin(2 * std::numbers::pi * 3.0 * x) * std::exp(-1.2 * x) + 0.1 * std::sin(40 * x); },
                {80, 255, 255}, "CH1 500mV  2ms");
  label(img, "LABO-SCOPE DS-1054", {30, 30}, 0.6, kDark, 2);
  label(img, "100 MHz  1 GSa/s", {300, 375}, 0.5, kDark);
  const double angles[] = {-40, 75, 160, -120, 20, 200};
  const cv::Scalar colours[] = {{60, 200, 230}, {230, 140, 60}, {120, 120, 120}, {60, 60, 220}, {120, 120, 120}, {90, 180, 90}};
  for (int i = 0; i < 6; ++i) {
    const cv::Point c(530 + (i % 3) * 90, 95 + (i / 3) * 110);
    knob(img, c, 28 - (i % 2) * 6, angles[i], colours[i]);
    label(img, std::string("CH") + std::to_string(i + 1), c + cv::Point(-18, 50), 0.4, kDark);
  }
  for (int i = 0; i < 5; ++i) button(img, {500 + i * 56, 290, 40, 22}, i == 2 ? cv::Scalar(50, 50, 210) : cv::Scalar(210, 210, 205), std::string(1, char('A' + i)));
  cv::circle(img, {760, 370}, 10, {40, 180, 40}, cv::FILLED, cv::LINE_AA);  // power LED, asymmetric
  return img;
}

cv::Mat draw_signal_generator_panel() {
  cv::Mat img(240, 720, CV_8UC3, cv::Scalar(200, 190, 160));
  cv::rectangle(img, {0, 0, 720, 240}, kDark, 8);
  digit_display(img, {24, 40, 300, 70}, "1.000 kHz", {60, 80, 255});
  label(img, "FUNCTION GENERATOR FG-220", {24, 30}, 0.55, kDark, 2);
  // Waveform selector icons: sine, square, triangle.
  for (int k = 0; k < 3; ++k) {
    const cv::Rect r(24 + k * 100, 140, 80, 50);
    cv::rectangle(img, r, kDark, 2);
    std::vector<cv::Point> pts;
    for (int x = 0; x <= 70; x += 2) {
      const double u = x / 70.0 * 2 * std::numbers::pi;
      double v = k == 0 ? std::sin(u) : k == 1 ? (std::sin(u) >= 0 ? 1.0 : -1.0) : (2 / std::numbers::pi) * std::asin(std::sin(u));
      pts.emplace_back(r.x + 5 + x, r.y + 25 - int(18 * v));
    }
    cv::polylines(img, pts, false, {160, 40, 40}, 2, cv::LINE_AA);
  }
  knob(img, {420, 95}, 40, 30, {60, 60, 60});
  label(img, "FREQ", {398, 165}, 0.5, kDark, 1);
  knob(img, {540, 80}, 24, 150, {200, 200, 200});
  label(img, "AMPL", {520, 125}, 0.45, kDark);
  knob(img, {630, 80}, 24, -60, {200, 200, 200});
  label(img, "OFFS", {610, 125}, 0.45, kDark);
  for (int i = 0; i < 3; ++i) {
    cv::circle(img, {540 + i * 60, 190}, 16, {30, 160, 200}, cv::FILLED, cv::LINE_AA);  // BNC outputs
    cv::circle(img, {540 + i * 60, 190}, 6, kDark, cv::FILLED, cv::LINE_AA);
  }
  label(img, "OUT  SYNC  MOD", {520, 225}, 0.45, kDark);
  return img;
}

cv::Mat draw_power_supply_panel() {
  cv::Mat img(400, 600, CV_8UC3, cv::Scalar(150, 160, 175));
  cv::rectangle(img, {0, 0, 600, 400}, kDark, 10);
  label(img, "DC POWER  0-30V 5A", {24, 36}, 0.7, kDark, 2);
  digit_display(img, {24, 60, 260, 80}, "12.04V", {40, 40, 240});
  digit_display(img, {316, 60, 260, 80}, "0.351A", {40, 220, 60});
  knob(img, {110, 240}, 46, 60, {50, 50, 50});
  label(img, "VOLTAGE", {70, 315}, 0.55, kDark, 1);
  knob(img, {300, 240}, 46, -150, {50, 50, 50});
  label(img, "CURRENT", {260, 315}, 0.55, kDark, 1);
  cv::circle(img, {440, 340}, 22, {30, 30, 200}, cv::FILLED, cv::LINE_AA);  // red terminal
  cv::circle(img, {520, 340}, 22, {30, 30, 30}, cv::FILLED, cv::LINE_AA);   // black terminal
  label(img, "+", {432, 300}, 0.9, kDark, 2);
  label(img, "-", {514, 300}, 0.9, kDark, 2);
  button(img, {420, 190, 60, 30}, {220, 220, 220}, "OUT");
  button(img, {500, 190, 60, 30}, {40, 200, 240}, "LOCK");
  cv::rectangle(img, {24, 360, 120, 20}, {40, 40, 40}, cv::FILLED);
  return img;
}

cv::Mat draw_landing_pattern() {
  // A large asymmetric target: concentric squares, an "H" and an arrow towards the front (+x world,
  // the template's top), with checker corners for the homography.
  cv::Mat img(600, 600, CV_8UC3, cv::Scalar(235, 235, 235));
  const cv::Scalar black(20, 20, 20), orange(0, 120, 250);
  for (int i = 0; i < 6; ++i) {
    for (int j = 0; j < 6; ++j) {
      if ((i == 0 || i == 5 || j == 0 || j == 5) && (i + j) % 2 == 0) cv::rectangle(img, {j * 100, i * 100, 100, 100}, black, cv::FILLED);
    }
  }
  cv::rectangle(img, {130, 130, 340, 340}, orange, 16);
  cv::rectangle(img, {230, 230, 30, 150}, black, cv::FILLED);
  cv::rectangle(img, {340, 230, 30, 150}, black, cv::FILLED);
  cv::rectangle(img, {230, 290, 140, 30}, black, cv::FILLED);
  cv::fillConvexPoly(img, std::vector<cv::Point>{{300, 150}, {350, 205}, {250, 205}}, black, cv::LINE_AA);
  cv::circle(img, {450, 450}, 12, black, cv::FILLED, cv::LINE_AA);
  return img;
}

std::vector<std::filesystem::path> write_instrument_templates(const std::filesystem::path& dir) {
  std::filesystem::create_directories(dir);
  const std::pair<const char*, cv::Mat> items[] = {{"oscilloscope.png", draw_oscilloscope_panel()},
                                                   {"signal_generator.png", draw_signal_generator_panel()},
                                                   {"power_supply.png", draw_power_supply_panel()},
                                                   {"landing_pattern.png", draw_landing_pattern()}};
  std::vector<std::filesystem::path> out;
  for (const auto& [name, img] : items) {
    const auto path = dir / name;
    if (!cv::imwrite(path.string(), img)) throw std::runtime_error("cannot write " + path.string());
    out.push_back(path);
  }
  return out;
}

}  // namespace labo::lab
