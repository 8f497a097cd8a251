#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "localization/planar/pose/planar_pose_filter.hpp"

using namespace labo;
using namespace labo::planar;

namespace {
constexpr double kDeg = M_PI / 180.0;

Eigen::Matrix3d noisy(const Eigen::Matrix3d& R, double sigma_rad, std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, sigma_rad);
  const Eigen::Vector3d w(n(rng), n(rng), n(rng));
  return Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix() * R;
}

double angle_deg(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
  return Eigen::AngleAxisd(a.transpose() * b).angle() / kDeg;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}
}  // namespace

TEST_CASE("planar: the pose filter averages a still panel's orientation below one frame's error") {
  std::mt19937 rng(5);
  const Eigen::Matrix3d truth = Eigen::AngleAxisd(0.3, Eigen::Vector3d(0.2, 1.0, 0.1).normalized()).toRotationMatrix();
  planar::PlanarPoseFilter filter;
  std::vector<double> raw, fused;
  for (int i = 0; i < 120; ++i) {
    const Eigen::Matrix3d measured = noisy(truth, 2.0 * kDeg, rng);
    const planar::FilteredOrientation f = filter.update(measured, 2.0 * kDeg, i / 30.0);
    if (i < 30) continue;  // settled
    raw.push_back(angle_deg(measured, truth));
    fused.push_back(angle_deg(f.R_cam_object, truth));
    CHECK(f.rotation_sigma_rad < 2.0 * kDeg);
  }
  INFO("raw median " << median(raw) << " deg, fused " << median(fused));
  CHECK(median(fused) < 0.5 * median(raw));
}

TEST_CASE("planar: the pose filter follows a steady turn without a steady lag") {
  std::mt19937 rng(6);
  planar::PlanarPoseFilter filter;
  const double rate = 20 * kDeg;  // rad/s about the camera's y axis (the drone yawing)
  double lag_sum_deg = 0;
  int late = 0;
  std::vector<double> raw, fused;
  for (int i = 0; i < 150; ++i) {
    const double t = i / 30.0;
    const Eigen::Matrix3d truth = Eigen::AngleAxisd(rate * t, Eigen::Vector3d::UnitY()).toRotationMatrix();
    const Eigen::Matrix3d measured = noisy(truth, 1.0 * kDeg, rng);
    const planar::FilteredOrientation f = filter.update(measured, 1.0 * kDeg, t);
    if (t <= 1.5) continue;  // the rate is being learnt
    const Eigen::AngleAxisd e(f.R_cam_object * truth.transpose());
    lag_sum_deg += (e.axis() * e.angle()).y() / kDeg;
    ++late;
    raw.push_back(angle_deg(measured, truth));
    fused.push_back(angle_deg(f.R_cam_object, truth));
  }
  INFO("mean error along the turn " << lag_sum_deg / late << " deg; raw median " << median(raw) << ", fused " << median(fused));
  CHECK(std::abs(lag_sum_deg / late) < 0.3);  // the rate is estimated: a constant turn leaves no lag
  CHECK(median(fused) < median(raw));
}

TEST_CASE("planar: the pose filter restarts on a gap, skips an outlier, and restarts on a lasting jump") {
  planar::PlanarPoseFilter filter;
  const Eigen::Matrix3d a = Eigen::Matrix3d::Identity();
  const Eigen::Matrix3d b = Eigen::AngleAxisd(30 * kDeg, Eigen::Vector3d::UnitX()).toRotationMatrix();
  CHECK(filter.update(a, 1 * kDeg, 0.0).restarted);
  for (int i = 1; i < 10; ++i) CHECK_FALSE(filter.update(a, 1 * kDeg, i / 30.0).restarted);
  // One frame 30 deg off at 1 deg sigma: skipped, the prediction stands.
  const planar::FilteredOrientation skipped = filter.update(b, 1 * kDeg, 10 / 30.0);
  CHECK(skipped.skipped);
  CHECK(angle_deg(skipped.R_cam_object, a) < 0.5);
  // The same jump persisting: the filter restarts on it (after max_skipped in a row).
  CHECK(filter.update(b, 1 * kDeg, 11 / 30.0).skipped);
  const planar::FilteredOrientation restarted = filter.update(b, 1 * kDeg, 12 / 30.0);
  CHECK(restarted.restarted);
  CHECK(angle_deg(restarted.R_cam_object, b) < 1e-9);
  // A gap longer than max_gap_s restarts; so does a measurement without a usable sigma.
  CHECK(filter.update(a, 1 * kDeg, 1.0).restarted);
  CHECK(filter.update(a, 0.0, 1.03).restarted);
  CHECK(filter.update(a, std::nan(""), 1.06).restarted);
  // A measurement whose own sigma is large barely moves a settled estimate.
  for (int i = 0; i < 30; ++i) filter.update(a, 1 * kDeg, 1.1 + i / 30.0);
  const planar::FilteredOrientation weak = filter.update(Eigen::AngleAxisd(10 * kDeg, Eigen::Vector3d::UnitX()).toRotationMatrix(),
                                                 15 * kDeg, 1.1 + 30 / 30.0);
  CHECK_FALSE(weak.skipped);
  CHECK(angle_deg(weak.R_cam_object, a) < 0.5);
}
