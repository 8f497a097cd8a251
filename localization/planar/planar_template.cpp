#include "localization/planar/planar_template.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace labo::planar {

namespace {

constexpr int kMinTemplateSidePx = 32;
constexpr double kEdgeGradient = 16.0;  // grey levels per pixel

std::string fixed(double v, int digits = 3) {
  std::ostringstream s;
  s.precision(digits);
  s << v;
  return s.str();
}

cv::Mat to_gray(const cv::Mat& image) {
  cv::Mat gray;
  if (image.channels() == 3) {
    cv::cvtColor(image, gray, cv::COLOR_BGR2GRAY);
  } else if (image.channels() == 4) {
    cv::cvtColor(image, gray, cv::COLOR_BGRA2GRAY);
  } else {
    gray = image.clone();
  }
  if (gray.depth() != CV_8U) {
    double lo = 0, hi = 0;
    cv::minMaxLoc(gray, &lo, &hi);
    gray.convertTo(gray, CV_8U, hi > lo ? 255.0 / (hi - lo) : 1.0, hi > lo ? -lo * 255.0 / (hi - lo) : 0.0);
  }
  return gray;
}

}  // namespace

TextureMeasures measure_texture(const cv::Mat& gray) {
  TextureMeasures m;
  cv::Scalar mean, stddev;
  cv::meanStdDev(gray, mean, stddev);
  m.intensity_stddev = stddev[0];
  cv::Mat gx, gy;
  cv::Sobel(gray, gx, CV_32F, 1, 0, 3, 1.0 / 8.0);
  cv::Sobel(gray, gy, CV_32F, 0, 1, 3, 1.0 / 8.0);
  double sxx = 0, syy = 0, sxy = 0;
  int edges = 0;
  for (int y = 1; y + 1 < gray.rows; ++y) {
    const float* px = gx.ptr<float>(y);
    const float* py = gy.ptr<float>(y);
    for (int x = 1; x + 1 < gray.cols; ++x) {
      sxx += px[x] * px[x];
      syy += py[x] * py[x];
      sxy += px[x] * py[x];
      if (px[x] * px[x] + py[x] * py[x] > kEdgeGradient * kEdgeGradient) ++edges;
    }
  }
  const int interior = std::max(1, (gray.rows - 2) * (gray.cols - 2));
  m.edge_fraction = static_cast<double>(edges) / interior;
  const double tr = sxx + syy, det = sxx * syy - sxy * sxy;
  const double disc = std::sqrt(std::max(0.0, tr * tr / 4 - det));
  const double l_max = tr / 2 + disc, l_min = tr / 2 - disc;
  m.gradient_isotropy = l_max > 0 ? std::max(0.0, l_min) / l_max : 0.0;
  return m;
}

PlanarTemplate PlanarTemplate::create(const cv::Mat& image, double width_m, double height_m, const std::string& name,
                                      const PlanarConfig& config) {
  auto refuse = [&](const std::string& why) {
    throw std::invalid_argument("template '" + name + "' refused: " + why);
  };
  if (image.empty()) refuse("the image is empty");
  if (image.cols < kMinTemplateSidePx || image.rows < kMinTemplateSidePx) {
    refuse("it is " + std::to_string(image.cols) + "x" + std::to_string(image.rows) + " px, at least " +
           std::to_string(kMinTemplateSidePx) + " px on each side is needed");
  }
  if (!std::isfinite(width_m) || !std::isfinite(height_m) || width_m <= 0 || height_m <= 0) {
    refuse("physical size " + fixed(width_m) + " x " + fixed(height_m) + " m must be positive");
  }
  PlanarTemplate t;
  t.name_ = name;
  t.width_m_ = width_m;
  t.height_m_ = height_m;
  t.original_size_ = image.size();
  const cv::Mat gray = to_gray(image);
  t.original_ = gray.clone();
  const double side = std::max(gray.cols, gray.rows);
  const double s = side > config.max_template_side_px ? config.max_template_side_px / side : 1.0;
  if (s < 1.0) {
    // An explicit size: given scale factors, OpenCV maps pixels by the factor rather than by the
    // ratio of the rounded sizes, which would shift the far edge by a fraction of a pixel.
    const cv::Size size(std::max(1, static_cast<int>(std::lround(gray.cols * s))),
                        std::max(1, static_cast<int>(std::lround(gray.rows * s))));
    cv::resize(gray, t.working_, size, 0, 0, cv::INTER_AREA);
  } else {
    t.working_ = gray;
  }
  // Exact scale between pixel-edge frames (resize rounds the size).
  const double sx = static_cast<double>(t.working_.cols) / gray.cols;
  const double sy = static_cast<double>(t.working_.rows) / gray.rows;
  t.working_from_original_ = cv::Matx33d(sx, 0, 0.5 * sx - 0.5, 0, sy, 0.5 * sy - 0.5, 0, 0, 1);

  const TextureMeasures m = measure_texture(t.working_);
  if (m.intensity_stddev < config.min_intensity_stddev) {
    refuse("too little texture to track: grey-level standard deviation " + fixed(m.intensity_stddev) +
           " < " + fixed(config.min_intensity_stddev));
  }
  if (m.edge_fraction < config.min_edge_fraction) {
    refuse("too little texture to track: only " + fixed(100 * m.edge_fraction) + " % of pixels on an edge, " +
           fixed(100 * config.min_edge_fraction) + " % needed");
  }
  if (m.gradient_isotropy < config.min_gradient_isotropy) {
    refuse("too little texture to track: its edges run in one direction only (isotropy " +
           fixed(m.gradient_isotropy) + " < " + fixed(config.min_gradient_isotropy) + ")");
  }
  return t;
}

PlanarTemplate PlanarTemplate::load(const std::filesystem::path& file, double width_m, double height_m,
                                    const PlanarConfig& config) {
  if (!std::filesystem::is_regular_file(file)) {
    throw std::invalid_argument("template '" + file.string() + "' refused: no such file");
  }
  const cv::Mat image = cv::imread(file.string(), cv::IMREAD_GRAYSCALE);
  if (image.empty()) {
    throw std::invalid_argument("template '" + file.string() + "' refused: not a readable image (PNG, JPEG, ...)");
  }
  return create(image, width_m, height_m, file.string(), config);
}

std::array<cv::Point2d, 4> PlanarTemplate::working_corners() const {
  const double w = working_.cols - 0.5, h = working_.rows - 0.5;
  return {cv::Point2d(-0.5, -0.5), cv::Point2d(w, -0.5), cv::Point2d(w, h), cv::Point2d(-0.5, h)};
}

std::array<cv::Point3d, 4> PlanarTemplate::object_corners() const {
  const double x = width_m_ / 2, y = height_m_ / 2;
  return {cv::Point3d(-x, -y, 0), cv::Point3d(x, -y, 0), cv::Point3d(x, y, 0), cv::Point3d(-x, y, 0)};
}

cv::Point2d apply_homography(const cv::Matx33d& H, const cv::Point2d& p) {
  const cv::Vec3d q = H * cv::Vec3d(p.x, p.y, 1.0);
  return {q[0] / q[2], q[1] / q[2]};
}

std::array<cv::Point2d, 4> map_corners(const cv::Matx33d& H, const std::array<cv::Point2d, 4>& corners) {
  std::array<cv::Point2d, 4> out;
  for (std::size_t i = 0; i < 4; ++i) out[i] = apply_homography(H, corners[i]);
  return out;
}

double corner_rms(const std::array<cv::Point2d, 4>& a, const std::array<cv::Point2d, 4>& b) {
  double sum = 0;
  for (std::size_t i = 0; i < 4; ++i) {
    const cv::Point2d d = a[i] - b[i];
    sum += d.dot(d);
  }
  return std::sqrt(sum / 4);
}

}  // namespace labo::planar
