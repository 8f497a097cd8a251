#include <catch2/catch.hpp>

#include "face_test_pose.hpp"
#include <numbers>
#include <random>

#include "core/candide3.hpp"
#include "localization/face/face_geometry.hpp"
#include "localization/face/face_landmark_model.hpp"
#include "localization/face/face_pose_solver.hpp"

using namespace labo;
using namespace labo::face;

namespace {
constexpr double kDeg = std::numbers::pi / 180.0;

FaceLandmarkModel test_model() {
  return make_face_landmark_model(Candide3Model::load(Candide3Model::default_path()),
                                  load_ibug68_mapping(default_ibug68_mapping_path()));
}

const IdealPinhole kCamera{569.9, 568.0, 331.4, 135.9};

PnpProblem project(const Eigen::Matrix3Xd& points, const Eigen::Isometry3d& T, double noise_px, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, noise_px);
  PnpProblem p{points, Eigen::Matrix2Xd(2, points.cols()), kCamera, {}};
  for (Eigen::Index i = 0; i < points.cols(); ++i) {
    p.pixels.col(i) = kCamera.project(T * points.col(i).eval()) + Eigen::Vector2d(noise(rng), noise(rng));
  }
  return p;
}

using testing::pose;

FacePoseSolverOptions with(PnpMethod method) {
  FacePoseSolverOptions o;
  o.method = method;
  return o;
}

double rotation_error_deg(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return Eigen::AngleAxisd(a.linear() * b.linear().transpose()).angle() / kDeg;
}
}  // namespace

TEST_CASE("face: head angles round-trip and the frontal face looks into the camera") {
  const HeadAngles a{0.3, -0.2, 0.4};
  const HeadAngles b = head_angles(head_rotation(a));
  CHECK(b.yaw == Approx(a.yaw).margin(1e-12));
  CHECK(b.pitch == Approx(a.pitch).margin(1e-12));
  CHECK(b.roll == Approx(a.roll).margin(1e-12));
  const Eigen::Vector3d los = line_of_sight(head_rotation({}));
  CHECK(los.isApprox(Eigen::Vector3d(0, 0, -1)));
  // +x of the face (subject's left) is image right: a frontal face's left eye has the larger u.
  const FaceLandmarkModel model = test_model();
  const Eigen::Matrix3Xd p = model.points_m(Eigen::VectorXd::Zero(model.shape_unit_count()), 0.063);
  const PnpProblem prob = project(p, pose(0, 0, 0, {0, 0, 1}), 0, 1);
  CHECK(prob.pixels(0, model.column_of(45)) > prob.pixels(0, model.column_of(36)));  // left eye outer right of right eye outer
  CHECK(prob.pixels(1, model.column_of(57)) > prob.pixels(1, model.column_of(27 + 3)));  // chin-ward lip below nose tip
}

TEST_CASE("face: the landmark model's metric scale matches the interpupillary distance") {
  const FaceLandmarkModel model = test_model();
  CHECK(model.size() == 43);
  const Eigen::VectorXd tau = Eigen::VectorXd::Constant(model.shape_unit_count(), 0.3);
  const Eigen::Matrix3Xd p = model.points_m(tau, 0.065);
  Eigen::Vector3d right = Eigen::Vector3d::Zero(), left = Eigen::Vector3d::Zero();
  for (int id = 36; id <= 41; ++id) right += p.col(model.column_of(id)) / 6.0;
  for (int id = 42; id <= 47; ++id) left += p.col(model.column_of(id)) / 6.0;
  CHECK((left - right).norm() == Approx(0.065).epsilon(1e-9));
}

TEST_CASE("face: every PnP method recovers exact synthetic projections") {
  const FaceLandmarkModel model = test_model();
  const Eigen::Matrix3Xd points = model.points_m(Eigen::VectorXd::Zero(model.shape_unit_count()), 0.063);
  for (const auto& truth : {pose(0, 0, 0, {0, 0, 0.6}), pose(40, -20, 15, {0.1, -0.05, 1.2}),
                            pose(-45, 25, -30, {-0.2, 0.1, 2.0})}) {
    const PnpProblem problem = project(points, truth, 0.0, 1);
    for (auto method : {PnpMethod::Epnp, PnpMethod::RansacP3p, PnpMethod::EpnpLm, PnpMethod::RansacP3pLm,
                        PnpMethod::LmTracking}) {
      FacePoseSolver solver(with(method));
      const auto est = solver.solve(problem);
      INFO(to_string(method));
      REQUIRE(est);
      // RANSAC P3P returns its best minimal solution unrefined: exact only up to P3P's numerics.
      const bool minimal = method == PnpMethod::RansacP3p;
      CHECK((est->solution.T_cam_face.translation() - truth.translation()).norm() < (minimal ? 0.01 : 1e-3));
      CHECK(rotation_error_deg(est->solution.T_cam_face, truth) < (minimal ? 1.0 : 0.1));
    }
  }
}

TEST_CASE("face: LM refinement beats the closed forms on noisy landmarks with outliers") {
  const FaceLandmarkModel model = test_model();
  const Eigen::Matrix3Xd points = model.points_m(Eigen::VectorXd::Zero(model.shape_unit_count()), 0.063);
  double err_epnp = 0, err_epnp_lm = 0, err_p3p_lm = 0;
  for (unsigned seed = 0; seed < 20; ++seed) {
    const Eigen::Isometry3d truth = pose(30, 10, -10, {0.05, 0.0, 1.0});
    PnpProblem problem = project(points, truth, 1.0, seed);
    problem.pixels.col(3) += Eigen::Vector2d(25, -10);  // two landmark outliers
    problem.pixels.col(20) += Eigen::Vector2d(-15, 20);
    FacePoseSolver epnp(with(PnpMethod::Epnp)), epnp_lm(with(PnpMethod::EpnpLm)), p3p_lm(with(PnpMethod::RansacP3pLm));
    err_epnp += rotation_error_deg(epnp.solve(problem)->solution.T_cam_face, truth);
    err_epnp_lm += rotation_error_deg(epnp_lm.solve(problem)->solution.T_cam_face, truth);
    err_p3p_lm += rotation_error_deg(p3p_lm.solve(problem)->solution.T_cam_face, truth);
  }
  CHECK(err_epnp_lm < err_epnp);
  CHECK(err_epnp_lm / 20 < 3.0);  // 1 px noise on a face 36 px between the eyes
  CHECK(err_p3p_lm / 20 < 3.0);
}

TEST_CASE("face: LM tracking starts from the previous pose and falls back to EPnP") {
  const FaceLandmarkModel model = test_model();
  const Eigen::Matrix3Xd points = model.points_m(Eigen::VectorXd::Zero(model.shape_unit_count()), 0.063);
  FacePoseSolver solver(with(PnpMethod::LmTracking));
  CHECK_FALSE(solver.has_previous());
  auto first = solver.solve(project(points, pose(10, 0, 0, {0, 0, 1}), 0.3, 1));
  REQUIRE(first);
  CHECK(first->reinitialised);  // nothing to track from
  auto second = solver.solve(project(points, pose(12, 1, 0, {0.01, 0, 1.01}), 0.3, 2));
  REQUIRE(second);
  CHECK_FALSE(second->reinitialised);
  CHECK((second->solution.T_cam_face.translation() - Eigen::Vector3d(0.01, 0, 1.01)).norm() < 0.02);
  solver.reset();
  auto after_reset = solver.solve(project(points, pose(12, 1, 0, {0.01, 0, 1.01}), 0.3, 3));
  REQUIRE(after_reset);
  CHECK(after_reset->reinitialised);

  // A tracked fit worse than the threshold is discarded and EPnP re-initialises.
  FacePoseSolverOptions strict = with(PnpMethod::LmTracking);
  strict.tracking_max_rms_px = 1e-6;
  FacePoseSolver picky(strict);
  REQUIRE(picky.solve(project(points, pose(0, 0, 0, {0, 0, 1}), 0.5, 4)));
  auto refit = picky.solve(project(points, pose(2, 0, 0, {0, 0, 1}), 0.5, 5));
  REQUIRE(refit);
  CHECK(refit->reinitialised);
  CHECK(rotation_error_deg(refit->solution.T_cam_face, pose(2, 0, 0, {0, 0, 1})) < 2.0);
}

TEST_CASE("face: PnP refuses too few points and poses behind the camera") {
  PnpProblem tiny{Eigen::Matrix3Xd::Random(3, 3), Eigen::Matrix2Xd::Random(2, 3), kCamera, {}};
  CHECK_FALSE(solve_epnp(tiny));
  std::mt19937 rng(1);
  CHECK_FALSE(solve_ransac_p3p(tiny, {}, rng));
  const FaceLandmarkModel model = test_model();
  const Eigen::Matrix3Xd points = model.points_m(Eigen::VectorXd::Zero(model.shape_unit_count()), 0.063);
  const PnpProblem problem = project(points, pose(0, 0, 0, {0, 0, 1}), 0, 1);
  CHECK_FALSE(refine_lm(problem, pose(0, 0, 0, {0, 0, -1}), {}));
  CHECK(parse_pnp_method("lm_tracking") == PnpMethod::LmTracking);
  CHECK_FALSE(parse_pnp_method("posit"));
}

TEST_CASE("face: LM weights take a point out of the refinement") {
  const FaceLandmarkModel model = test_model();
  const Eigen::Matrix3Xd points = model.points_m(Eigen::VectorXd::Zero(model.shape_unit_count()), 0.063);
  const Eigen::Isometry3d truth = pose(20, -10, 5, {0.02, -0.01, 1.0});
  PnpProblem problem = project(points, truth, 0.0, 1);
  problem.pixels.col(0) += Eigen::Vector2d(25, -15);  // one landmark far off
  LmOptions lm;
  lm.huber_px = 1e6;  // plain least squares: the bad point pulls the pose unless its weight is 0
  const auto pulled = refine_lm(problem, pose(15, -5, 0, {0, 0, 1.1}), lm);
  REQUIRE(pulled);
  CHECK(rotation_error_deg(pulled->T_cam_face, truth) > 0.2);
  problem.weights = Eigen::VectorXd::Ones(points.cols());
  problem.weights(0) = 0;
  const auto clean = refine_lm(problem, pose(15, -5, 0, {0, 0, 1.1}), lm);
  REQUIRE(clean);
  CHECK(rotation_error_deg(clean->T_cam_face, truth) < 0.01);
  CHECK((clean->T_cam_face.translation() - truth.translation()).norm() < 1e-4);
}
