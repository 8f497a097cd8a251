// LaboDrone's IPPE (localization/planar/pose/ippe.hpp) against OpenCV's cv::solvePnPGeneric(SOLVEPNP_IPPE),
// which it replaces in the planar localizer: the same two poses and reprojection errors to 1e-9 on
// near-fronto-parallel and oblique views, exact and noisy corners.
#include <catch2/catch.hpp>

#include <cmath>
#include <random>
#include <vector>

#include <opencv2/calib3d.hpp>

#include "localization/planar/pose/ippe.hpp"
#include "bench/planar/synthetic_scene.hpp"

using namespace labo;
using namespace labo::bench;
using namespace labo::planar;

namespace {

struct Reference {
  Eigen::Matrix3d R;
  Eigen::Vector3d t;
  double rms_px;
};

std::vector<Reference> opencv_ippe(const std::array<Eigen::Vector2d, 4>& object_xy, const std::array<Eigen::Vector2d, 4>& image_px,
                                   const cv::Matx33d& K) {
  std::vector<cv::Point3d> object;
  std::vector<cv::Point2d> image;
  for (std::size_t i = 0; i < 4; ++i) {
    object.emplace_back(object_xy[i].x(), object_xy[i].y(), 0.0);
    image.emplace_back(image_px[i].x(), image_px[i].y());
  }
  std::vector<cv::Mat> rvecs, tvecs;
  std::vector<double> errors;
  cv::solvePnPGeneric(object, image, K, cv::noArray(), rvecs, tvecs, false, cv::SOLVEPNP_IPPE, cv::noArray(), cv::noArray(),
                      errors);
  std::vector<Reference> out;
  for (std::size_t i = 0; i < rvecs.size(); ++i) {
    cv::Matx33d R;
    cv::Rodrigues(rvecs[i], R);
    Reference r;
    for (int a = 0; a < 3; ++a) {
      for (int b = 0; b < 3; ++b) r.R(a, b) = R(a, b);
      r.t(a) = tvecs[i].at<double>(a);
    }
    r.rms_px = errors[i];
    out.push_back(r);
  }
  return out;
}

struct View {
  double tilt_deg;
  double distance_m;
  double noise_px;
};

}  // namespace

TEST_CASE("ippe: the two poses and their errors equal OpenCV's SOLVEPNP_IPPE to 1e-9") {
  const cv::Matx33d K(569.8, 0, 318.4, 0, 566.1, 183.7, 0, 0, 1);
  const planar::IppeIntrinsics intrinsics{K(0, 0), K(1, 1), K(0, 2), K(1, 2)};
  std::mt19937 rng(20261203);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::normal_distribution<double> gauss(0.0, 1.0);
  // Seen along the normal, near fronto-parallel (the panel at range, where the two solutions are both
  // plausible) to oblique; exact corners and corners with tracker-like noise.
  const std::vector<View> views{{0.0, 2.0, 0.0}, {0.3, 3.0, 0.0}, {1.0, 5.0, 0.0}, {2.0, 2.0, 0.3}, {5.0, 1.2, 0.0}, {15.0, 0.6, 0.5},
                                {30.0, 2.5, 0.0}, {45.0, 1.5, 0.2}, {60.0, 0.8, 0.0}, {70.0, 3.5, 0.4}, {0.5, 6.0, 0.3}};
  int compared = 0;
  for (const View& view : views) {
    for (int trial = 0; trial < 20; ++trial) {
      const double w = 0.2 + 0.3 * std::abs(unit(rng)), h = 0.15 + 0.25 * std::abs(unit(rng));
      const std::array<Eigen::Vector2d, 4> object{Eigen::Vector2d(-w / 2, -h / 2), Eigen::Vector2d(w / 2, -h / 2),
                                                  Eigen::Vector2d(w / 2, h / 2), Eigen::Vector2d(-w / 2, h / 2)};
      const double tilt = view.tilt_deg * M_PI / 180.0, azimuth = M_PI * unit(rng);
      const Eigen::Vector3d camera = view.distance_m * Eigen::Vector3d(std::sin(tilt) * std::cos(azimuth),
                                                                      std::sin(tilt) * std::sin(azimuth), -std::cos(tilt));
      // Aimed beside the panel's centre, so that it is off the optical axis, and rolled.
      const Eigen::Vector3d target(0.3 * w * unit(rng), 0.3 * h * unit(rng), 0.0);
      const Eigen::Isometry3d T = look_at_object(camera, target, 0.3 * unit(rng));
      std::array<Eigen::Vector2d, 4> image;
      for (std::size_t i = 0; i < 4; ++i) {
        const Eigen::Vector3d p = T * Eigen::Vector3d(object[i].x(), object[i].y(), 0.0);
        image[i] = Eigen::Vector2d(K(0, 0) * p.x() / p.z() + K(0, 2), K(1, 1) * p.y() / p.z() + K(1, 2)) +
                   view.noise_px * Eigen::Vector2d(gauss(rng), gauss(rng));
      }
      const auto ours = ippe_four_points(object, image, intrinsics);
      const std::vector<Reference> reference = opencv_ippe(object, image, K);
      INFO("tilt " << view.tilt_deg << " deg, " << view.distance_m << " m, noise " << view.noise_px << " px, trial " << trial);
      REQUIRE(ours);
      REQUIRE(reference.size() == 2);
      if (view.tilt_deg == 0.0) {
        // The camera on the panel's normal through the centroid: the tilt is then a square root of
        // rounding errors (the third column's entries are sqrt(1 - |row|^2), 1e-16 under the root):
        // both implementations are within sqrt(eps) ~ 1e-8 of the truth, and OpenCV 4.6 returns NaN
        // when the rounding makes the root's argument negative (LaboDrone's clamps it to zero).
        for (const planar::IppeSolution& s : *ours) {
          CHECK((s.R - T.linear()).cwiseAbs().maxCoeff() < 1e-7);
          CHECK((s.t - T.translation()).cwiseAbs().maxCoeff() < 1e-7);
        }
        for (const Reference& ref : reference) {
          if (ref.R.allFinite()) CHECK((ref.R - T.linear()).cwiseAbs().maxCoeff() < 1e-7);
        }
        compared += 2;
        continue;
      }
      // Matched by pose (two solutions with nearly equal errors may come in either order).
      for (const Reference& ref : reference) {
        const planar::IppeSolution* nearest = nullptr;
        double nearest_difference = 1e300;
        for (const planar::IppeSolution& s : *ours) {
          const double difference = (s.R - ref.R).cwiseAbs().maxCoeff() + (s.t - ref.t).cwiseAbs().maxCoeff();
          if (difference < nearest_difference) nearest_difference = difference, nearest = &s;
        }
        REQUIRE(nearest != nullptr);
        CHECK((nearest->R - ref.R).cwiseAbs().maxCoeff() < 1e-9);
        CHECK((nearest->t - ref.t).cwiseAbs().maxCoeff() < 1e-9 * std::max(1.0, ref.t.norm()));
        CHECK(std::abs(nearest->rms_px - ref.rms_px) < 1e-9);
        ++compared;
      }
      // Lower reprojection error first.
      CHECK(ours->at(0).rms_px <= ours->at(1).rms_px);
    }
  }
  CHECK(compared == 2 * 20 * static_cast<int>(views.size()));
}

TEST_CASE("ippe: exact corners give the true pose, collinear corners give none") {
  const planar::IppeIntrinsics intrinsics{570, 570, 320, 180};
  const std::array<Eigen::Vector2d, 4> object{Eigen::Vector2d(-0.2, -0.1), Eigen::Vector2d(0.2, -0.1), Eigen::Vector2d(0.2, 0.1),
                                              Eigen::Vector2d(-0.2, 0.1)};
  const Eigen::Isometry3d truth = look_at_object(Eigen::Vector3d(0.5, -0.3, -1.1), Eigen::Vector3d(0.03, 0.01, 0), 0.2);
  std::array<Eigen::Vector2d, 4> image;
  for (std::size_t i = 0; i < 4; ++i) {
    const Eigen::Vector3d p = truth * Eigen::Vector3d(object[i].x(), object[i].y(), 0.0);
    image[i] = Eigen::Vector2d(570 * p.x() / p.z() + 320, 570 * p.y() / p.z() + 180);
  }
  const auto poses = ippe_four_points(object, image, intrinsics);
  REQUIRE(poses);
  CHECK((poses->at(0).R - truth.linear()).cwiseAbs().maxCoeff() < 1e-12);
  CHECK((poses->at(0).t - truth.translation()).norm() < 1e-12);
  CHECK(poses->at(0).rms_px < 1e-9);
  CHECK(poses->at(1).rms_px > 0.1);  // the other solution does not fit exact corners of an oblique view
  CHECK((poses->at(1).R.transpose() * poses->at(1).R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() < 1e-12);
  CHECK(poses->at(1).R.determinant() == Approx(1.0).epsilon(1e-12));

  std::array<Eigen::Vector2d, 4> collinear = image;
  collinear[2] = 0.5 * (collinear[0] + collinear[1]);
  CHECK_FALSE(ippe_four_points(object, collinear, intrinsics).has_value());
}
