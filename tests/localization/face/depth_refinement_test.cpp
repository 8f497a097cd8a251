#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "core/candide3.hpp"
#include "localization/face/depth_refinement.hpp"
#include "localization/face/face_geometry.hpp"

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

// The person's true landmarks: the registered ones 30 % deeper about their mean depth (a face the
// model makes too shallow), the brows 3 mm deeper still, their outer ends 8 mm more (on the temples)
// and the nose base 2 mm farther out; in the image plane the registered ones (the frontal picture saw
// that). Less the part of the difference that is linear in x and y: that part is, to first order, a
// tilt of the face frame, which no sequence can tell from the poses (the refinement leaves it alone
// by design; here it would show as a constant pitch offset of every pose).
Eigen::Matrix3Xd deeper_face(const FaceLandmarkModel& model, const Eigen::Matrix3Xd& registered) {
  const Eigen::Index n = registered.cols();
  const double mean_z = registered.row(2).mean();
  Eigen::VectorXd d(n);
  for (Eigen::Index j = 0; j < n; ++j) {
    const int id = model.landmark_ids()[static_cast<std::size_t>(j)];
    d(j) = 0.3 * (registered(2, j) - mean_z) + (id <= 26 ? -0.003 : 0.0) + (id >= 31 && id <= 35 ? 0.002 : 0.0) +
           (id == 17 || id == 26 ? -0.008 : 0.0);
  }
  Eigen::MatrixXd G(n, 3);
  G << Eigen::VectorXd::Ones(n), registered.row(0).transpose(), registered.row(1).transpose();
  d -= G * G.colPivHouseholderQr().solve(d);
  Eigen::Matrix3Xd truth = registered;
  truth.row(2) += d.transpose();
  return truth;
}

// Views of `truth` over a grid of yaw and pitch, 1 px noise, first poses off by 20 % of the angles.
std::vector<DepthView> turning_views(const Eigen::Matrix3Xd& truth, double yaw_deg, double pitch_deg, std::mt19937& rng) {
  std::vector<DepthView> views;
  for (double a : {-1.0, -0.5, 0.0, 0.5, 1.0}) {
    for (double b : {-1.0, -0.5, 0.0, 0.5, 1.0}) {
      views.push_back({project(truth, head_pose(a * yaw_deg, b * pitch_deg, 0.8), 1.0, rng),
                       head_pose(0.8 * a * yaw_deg, 0.8 * b * pitch_deg, 0.85)});
    }
  }
  return views;
}

// Pitch error (degrees) of the LM pose of a head at yaw 25°, pitch 18° seen exactly, posed with `points`.
double pitch_error_deg(const Eigen::Matrix3Xd& points, const Eigen::Matrix3Xd& truth) {
  const Eigen::Isometry3d T = head_pose(25, 18, 1.0);
  std::mt19937 rng(7);
  const PnpProblem problem{points, project(truth, T, 0.0, rng), kCamera, {}};
  const auto s = refine_lm(problem, head_pose(20, 10, 0.9), LmOptions{});
  REQUIRE(s);
  return std::abs(head_angles(s->T_cam_face.linear()).pitch - 18 * kRad) / kRad;
}

Eigen::Matrix3Xd with_depth(Eigen::Matrix3Xd points, const Eigen::VectorXd& change) {
  points.row(2) += change.transpose();
  return points;
}

double depth_rms_mm(const Eigen::Matrix3Xd& p, const Eigen::Matrix3Xd& truth) {
  const Eigen::VectorXd d = (p.row(2) - truth.row(2)).transpose();
  return 1000.0 * std::sqrt((d.array() - d.mean()).square().mean());
}

}  // namespace

TEST_CASE("face: depth components are orthogonal to the face frame's tilts and to each other") {
  const FaceLandmarkModel model = landmark_model();
  const Eigen::Matrix3Xd points = model.points_m(Eigen::VectorXd::Zero(model.shape_unit_count()), kIpd);
  const Eigen::MatrixXd B = depth_components(model, points);
  REQUIRE(B.rows() == model.size());
  REQUIRE(B.cols() >= 3);  // the gain and several regions survive the gauge
  const double n = static_cast<double>(B.rows());
  CHECK((B.transpose() * B / n - Eigen::MatrixXd::Identity(B.cols(), B.cols())).cwiseAbs().maxCoeff() < 1e-9);
  CHECK((B.transpose() * Eigen::VectorXd::Ones(B.rows())).cwiseAbs().maxCoeff() < 1e-9);
  CHECK((B.transpose() * points.row(0).transpose()).cwiseAbs().maxCoeff() < 1e-9);
  CHECK((B.transpose() * points.row(1).transpose()).cwiseAbs().maxCoeff() < 1e-9);
  // The first is the depth profile itself (a gain): it correlates strongly with the points' depth.
  const Eigen::VectorXd z = points.row(2).transpose().array() - points.row(2).mean();
  CHECK(std::abs(B.col(0).dot(z)) / (B.col(0).norm() * z.norm()) > 0.8);
}

TEST_CASE("face: the landmarks' depth comes back from views of a turning head, and the pitch with it") {
  const FaceLandmarkModel model = landmark_model();
  const Eigen::Matrix3Xd registered = model.points_m(Eigen::VectorXd::Zero(model.shape_unit_count()), kIpd);
  const Eigen::Matrix3Xd truth = deeper_face(model, registered);
  std::mt19937 rng(3);
  const std::vector<DepthView> views = turning_views(truth, 20, 12, rng);
  DepthRefinementOptions options;
  bool per_landmark = GENERATE(false, true);
  if (per_landmark) options.landmark_prior_sigma_m = 0.006;
  INFO("each landmark's own depth too: " << per_landmark);
  const DepthRefinement fit = refine_depth_from_views(model, registered, views, kCamera, options);
  INFO(fit.reason);
  REQUIRE(fit.accepted);
  CHECK(fit.views == 25);
  CHECK(fit.yaw_span_rad / kRad == Approx(32).margin(0.5));  // the first poses' spread
  CHECK(fit.rms_after_px < fit.rms_before_px);
  CHECK(fit.rms_after_px < 1.6);  // 1 px per axis: 1.41 px per point
  REQUIRE(fit.poses.size() == views.size());

  const Eigen::Matrix3Xd refined = with_depth(registered, fit.depth_change_m);
  CHECK(refined.topRows(2) == registered.topRows(2));  // the frontal picture's in-plane positions stay
  const double before_mm = depth_rms_mm(registered, truth), after_mm = depth_rms_mm(refined, truth);
  INFO("depth RMS before " << before_mm << " mm, after " << after_mm << " mm");
  // The components alone cannot place the brows' outer ends; each landmark's own depth can.
  CHECK(after_mm < (per_landmark ? 0.3 : 0.45) * before_mm);
  const double pitch_before = pitch_error_deg(registered, truth), pitch_after = pitch_error_deg(refined, truth);
  INFO("pitch error before " << pitch_before << " deg, after " << pitch_after << " deg");
  CHECK(pitch_before > 1.0);
  CHECK(pitch_after < 0.3 * pitch_before);
}

TEST_CASE("face: depth refinement refuses too few views or too little turn, and changes nothing") {
  const FaceLandmarkModel model = landmark_model();
  const Eigen::Matrix3Xd registered = model.points_m(Eigen::VectorXd::Zero(model.shape_unit_count()), kIpd);
  const Eigen::Matrix3Xd truth = deeper_face(model, registered);
  std::mt19937 rng(5);
  const auto refused = [](const DepthRefinement& r) {
    CHECK_FALSE(r.accepted);
    CHECK(r.depth_change_m.cwiseAbs().maxCoeff() == 0.0);
    CHECK(r.coefficients_m.cwiseAbs().maxCoeff() == 0.0);
  };
  std::vector<DepthView> views = turning_views(truth, 20, 12, rng);
  views.resize(8);
  const DepthRefinement few = refine_depth_from_views(model, registered, views, kCamera);
  refused(few);
  CHECK_THAT(few.reason, Catch::Contains("8 views, expected at least 10"));

  // Turned left and right only: the nod is what the pitch needs.
  const DepthRefinement no_nod = refine_depth_from_views(model, registered, turning_views(truth, 20, 2, rng), kCamera);
  refused(no_nod);
  CHECK_THAT(no_nod.reason, Catch::Contains("of pitch, expected at least") && Catch::Contains("3.2° of pitch"));
  const DepthRefinement still = refine_depth_from_views(model, registered, turning_views(truth, 1, 1, rng), kCamera);
  refused(still);
  CHECK_THAT(still.reason, Catch::Contains("1.6° of yaw"));
}

TEST_CASE("face: depth refinement refuses a fit that diverges or leaves the face implausible") {
  const FaceLandmarkModel model = landmark_model();
  const Eigen::Matrix3Xd registered = model.points_m(Eigen::VectorXd::Zero(model.shape_unit_count()), kIpd);
  std::mt19937 rng(9);
  const auto refused = [](const DepthRefinement& r) {
    CHECK_FALSE(r.accepted);
    CHECK(r.depth_change_m.cwiseAbs().maxCoeff() == 0.0);
  };
  SECTION("landmarks of no rigid face: each view's points shuffled") {
    std::vector<DepthView> views = turning_views(registered, 20, 12, rng);
    for (auto& v : views) {
      std::uniform_int_distribution<Eigen::Index> pick(0, v.pixels.cols() - 1);
      for (Eigen::Index j = 0; j < v.pixels.cols(); ++j) v.pixels.col(j).swap(v.pixels.col(pick(rng)));
    }
    const DepthRefinement r = refine_depth_from_views(model, registered, views, kCamera);
    refused(r);
    CHECK_THAT(r.reason, Catch::Contains("px RMS, expected at most 3.00 px"));
  }
  SECTION("a face three times as deep as the model: beyond a plausible change") {
    Eigen::Matrix3Xd deep = registered;
    deep.row(2) = (registered.row(2).array() - registered.row(2).mean()) * 3.0 + registered.row(2).mean();
    DepthRefinementOptions loose;
    loose.prior_sigma_m = 0.05;
    const DepthRefinement r = refine_depth_from_views(model, registered, turning_views(deep, 20, 12, rng), kCamera, loose);
    refused(r);
    CHECK_THAT(r.reason, Catch::Contains("would change by") && Catch::Contains("expected at most 15.0 mm"));
  }
  SECTION("first poses behind the camera: no finite fit") {
    std::vector<DepthView> views = turning_views(registered, 20, 12, rng);
    for (auto& v : views) v.T_cam_face_initial.translation().z() = -0.8;
    for (auto& v : views) v.pixels.setConstant(std::numeric_limits<double>::quiet_NaN());
    const DepthRefinement r = refine_depth_from_views(model, registered, views, kCamera);
    refused(r);
    CHECK_THAT(r.reason, Catch::Contains("diverged"));
  }
  SECTION("mismatched sizes are a programming error") {
    std::vector<DepthView> views = turning_views(registered, 20, 12, rng);
    views[3].pixels.conservativeResize(2, 10);
    CHECK_THROWS_WITH(refine_depth_from_views(model, registered, views, kCamera), Catch::Contains("view 3 has 10 landmarks"));
    CHECK_THROWS_WITH(refine_depth_from_views(model, registered.leftCols(5), views, kCamera),
                      Catch::Contains("5 points"));
  }
}
