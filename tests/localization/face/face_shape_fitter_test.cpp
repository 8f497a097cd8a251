#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "core/candide3.hpp"
#include "localization/face/face_geometry.hpp"
#include "localization/face/face_shape_fitter.hpp"

using namespace labo;
using namespace labo::face;

namespace {
const IdealPinhole kCamera{569.9, 568.0, 331.4, 135.9};

Eigen::Matrix2Xd project(const Eigen::Matrix3Xd& points, const Eigen::Isometry3d& T, double noise_px, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, noise_px);
  Eigen::Matrix2Xd px(2, points.cols());
  for (Eigen::Index i = 0; i < points.cols(); ++i) {
    px.col(i) = kCamera.project(T * points.col(i).eval()) + Eigen::Vector2d(noise(rng), noise(rng));
  }
  return px;
}
}  // namespace

// A common shift of the four "vertical position" units moves every landmark alike: from one picture it
// is the same as moving the face's origin, so only the shape up to a translation is identifiable.
double centred_shape_error_m(const FaceLandmarkModel& model, const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  Eigen::Matrix3Xd pa = model.points_m(a, 0.063), pb = model.points_m(b, 0.063);
  pa.colwise() -= pa.rowwise().mean();
  pb.colwise() -= pb.rowwise().mean();
  return std::sqrt((pa - pb).colwise().squaredNorm().mean());
}

TEST_CASE("face: shape fit recovers known shape parameters from a frontal view") {
  const FaceLandmarkModel model = make_face_landmark_model(Candide3Model::load(Candide3Model::default_path()),
                                                           load_ibug68_mapping(default_ibug68_mapping_path()));
  const auto observable = model.observable_units();
  // Head height, cheeks z, nose z-extension, nose pointing up and chin width move no landmark
  // (enough) in the image plane of a frontal view.
  for (int u : {0, 6, 7, 9, 13}) CHECK_FALSE(observable[static_cast<std::size_t>(u)]);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> value(-0.4, 0.4);
  Eigen::VectorXd truth = Eigen::VectorXd::Zero(model.shape_unit_count());
  for (std::size_t u = 0; u < observable.size(); ++u) {
    if (observable[u]) truth(static_cast<Eigen::Index>(u)) = value(rng);
  }
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = head_rotation({0.05, -0.03, 0.02});
  T.translation() = Eigen::Vector3d(0.02, -0.01, 0.8);
  const Eigen::VectorXd mean_shape = Eigen::VectorXd::Zero(model.shape_unit_count());

  SECTION("exact landmarks, almost no prior: the parameters and the distance come back") {
    ShapeFitOptions o;
    o.regularisation = 1e-6;
    o.alternations = 15;
    const ShapeFit fit = fit_shape(model, project(model.points_m(truth, 0.063), T, 0, 1), kCamera, 0.063, o);
    // Units that change the face's proportions come back exactly ...
    for (int u : {3, 4, 5, 11, 12}) CHECK(fit.shape_params(u) == Approx(truth(u)).margin(0.01));
    // ... the vertical positions up to their common shift (brows 1, eyes 2, nose 8, mouth 10).
    const double shift = fit.shape_params(2) - truth(2);
    for (int u : {1, 8, 10}) CHECK(fit.shape_params(u) - truth(u) == Approx(shift).margin(0.01));
    CHECK(centred_shape_error_m(model, fit.shape_params, truth) < 2e-4);
    CHECK(fit.rms_px < 0.05);
    CHECK(fit.rms_px_mean_shape > 1.0);
    CHECK(std::abs(fit.T_cam_face.translation().z() - 0.8) < 0.005);
  }
  SECTION("noisy landmarks, default prior: much closer than the mean shape") {
    const ShapeFit fit = fit_shape(model, project(model.points_m(truth, 0.063), T, 0.7, 2), kCamera, 0.063);
    CHECK(centred_shape_error_m(model, fit.shape_params, truth) < 0.5 * centred_shape_error_m(model, mean_shape, truth));
    CHECK(fit.rms_px < fit.rms_px_mean_shape);
  }
  SECTION("bad inputs are refused") {
    CHECK_THROWS_AS(fit_shape(model, Eigen::Matrix2Xd::Zero(2, 5), kCamera, 0.063), std::invalid_argument);
    CHECK_THROWS_AS(fit_shape(model, project(model.points_m(truth, 0.063), T, 0, 1), kCamera, 0.0), std::invalid_argument);
  }
}
