#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "core/candide3.hpp"
#include "localization/face/face_geometry.hpp"
#include "localization/face/multi_view_landmarks.hpp"

using namespace labo;
using namespace labo::face;

namespace {

const IdealPinhole kCamera{569.9, 568.0, 331.4, 135.9};
constexpr double kIpd = 0.063;
constexpr double kRad = 3.14159265358979323846 / 180.0;

FaceLandmarkModel landmark_model() {
  return make_face_landmark_model(Candide3Model::load(Candide3Model::default_path()),
                                  load_ibug68_mapping(default_ibug68_mapping_path()));
}

double ipd_of(const FaceLandmarkModel& model, const Eigen::Matrix3Xd& p) {
  Eigen::Vector3d r = Eigen::Vector3d::Zero(), l = Eigen::Vector3d::Zero();
  for (int k = 0; k < 6; ++k) {
    r += p.col(model.column_of(36 + k));
    l += p.col(model.column_of(42 + k));
  }
  return (l - r).norm() / 6.0;
}

Eigen::Isometry3d head_pose(double yaw_deg, double pitch_deg, double distance_m) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = head_rotation({yaw_deg * kRad, pitch_deg * kRad, 0.0});
  T.translation() << 0.01, -0.02, distance_m;
  return T;
}

Eigen::Matrix2Xd project(const Eigen::Matrix3Xd& points, const Eigen::Isometry3d& T, double noise_px, std::mt19937& rng) {
  std::normal_distribution<double> noise(0.0, noise_px);
  Eigen::Matrix2Xd px(2, points.cols());
  for (Eigen::Index j = 0; j < points.cols(); ++j) {
    px.col(j) = kCamera.project(T * points.col(j).eval()) + Eigen::Vector2d(noise(rng), noise(rng));
  }
  return px;
}

// Pitch error of the LM pose of a turned head seen exactly (no noise) with `points` as the model.
double pitch_error_deg(const Eigen::Matrix3Xd& points, const Eigen::Matrix3Xd& truth) {
  const Eigen::Isometry3d T = head_pose(25, 18, 1.0);
  std::mt19937 rng(7);
  PnpProblem problem;
  problem.points_face = points;
  problem.pixels = project(truth, T, 0.0, rng);
  problem.camera = kCamera;
  const auto s = refine_lm(problem, head_pose(20, 10, 0.9), LmOptions{});
  REQUIRE(s);
  return std::abs(head_angles(s->T_cam_face.linear()).pitch - 18 * kRad) / kRad;
}

}  // namespace

TEST_CASE("face: the depth of the landmarks comes back from views of a turning head") {
  const FaceLandmarkModel model = landmark_model();
  const Eigen::Matrix3Xd mapped = model.points_m(Eigen::VectorXd::Zero(model.shape_unit_count()), kIpd);
  // The person's true landmarks: the model's with the brows 5 mm deeper and the nose 6 mm farther
  // out, each point also 2 mm off in depth at random: what a frontal picture cannot see. In the
  // image plane they are the model's (the registration saw that); an in-plane error of the model
  // would also turn the face frame the refinement settles on (by ~1 deg for 1 mm, docs/face.md).
  std::mt19937 rng(3);
  std::normal_distribution<double> depth(0.0, 0.002), lateral(0.0, 0.0);
  Eigen::Matrix3Xd truth = mapped;
  for (Eigen::Index j = 0; j < truth.cols(); ++j) {
    const int id = model.landmark_ids()[static_cast<std::size_t>(j)];
    const double shift = id >= 17 && id <= 26 ? -0.005 : (id >= 27 && id <= 35 ? 0.006 : 0.0);
    truth.col(j) += Eigen::Vector3d(lateral(rng), lateral(rng), shift + depth(rng));
  }
  truth *= kIpd / ipd_of(model, truth);

  std::vector<LandmarkView> views;
  for (double yaw : {-20.0, -10.0, 0.0, 10.0, 20.0}) {
    for (double pitch : {-12.0, -6.0, 0.0, 6.0, 12.0}) {
      const Eigen::Isometry3d T = head_pose(yaw, pitch, 0.8);
      views.push_back({project(truth, T, 1.0, rng), head_pose(yaw * 0.8, pitch * 0.8, 0.85)});
    }
  }
  const MultiViewFit fit = refine_landmarks_from_views(model, mapped, views, kCamera, kIpd);
  REQUIRE(fit.points_m.cols() == model.size());
  CHECK(ipd_of(model, fit.points_m) == Approx(kIpd).epsilon(1e-9));
  CHECK(fit.rms_after_px < fit.rms_before_px);
  CHECK(fit.rms_after_px < 1.6);  // the noise was 1 px per axis: 1.41 px per point

  // Depth of the points (relative to their mean, the rigid part being the poses') against the truth.
  const auto depth_rms = [&](const Eigen::Matrix3Xd& p) {
    const Eigen::VectorXd d = (p.row(2) - truth.row(2)).transpose();
    return std::sqrt((d.array() - d.mean()).square().mean());
  };
  const double before_mm = 1000 * depth_rms(mapped), after_mm = 1000 * depth_rms(fit.points_m);
  INFO("depth RMS before " << before_mm << " mm, after " << after_mm << " mm");
  CHECK(after_mm < 0.5 * before_mm);

  // What it is for: the pitch of a turned head posed with the refined landmarks.
  const double pitch_before = pitch_error_deg(mapped, truth), pitch_after = pitch_error_deg(fit.points_m, truth);
  INFO("pitch error before " << pitch_before << " deg, after " << pitch_after << " deg");
  CHECK(pitch_after < 0.5 * pitch_before);
}

TEST_CASE("face: multi-view landmark refinement refuses too few or mismatched views") {
  const FaceLandmarkModel model = landmark_model();
  const Eigen::Matrix3Xd mapped = model.points_m(Eigen::VectorXd::Zero(model.shape_unit_count()), kIpd);
  std::mt19937 rng(1);
  const LandmarkView good{project(mapped, head_pose(0, 0, 0.8), 0.5, rng), head_pose(0, 0, 0.8)};
  CHECK_THROWS_WITH(refine_landmarks_from_views(model, mapped, {good, good}, kCamera, kIpd),
                    Catch::Contains("2 views, expected at least 3"));
  LandmarkView short_view = good;
  short_view.pixels.conservativeResize(2, 10);
  CHECK_THROWS_WITH(refine_landmarks_from_views(model, mapped, {good, good, short_view}, kCamera, kIpd),
                    Catch::Contains("view 2 has 10 landmarks"));
  CHECK_THROWS_WITH(refine_landmarks_from_views(model, mapped.leftCols(5), {good, good, good}, kCamera, kIpd),
                    Catch::Contains("5 model points"));
}
