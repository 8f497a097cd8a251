#include <catch2/catch.hpp>

#include "face_test_pose.hpp"
#include <numbers>
#include <opencv2/imgproc.hpp>

#include "core/camera_model.hpp"
#include "core/candide3.hpp"
#include "localization/face/face_geometry.hpp"
#include "localization/face/face_landmark_model.hpp"
#include "localization/face/frontal_view.hpp"
#include "localization/face/landmark_weights.hpp"

using namespace labo;
using namespace labo::face;

namespace {
constexpr double kDeg = std::numbers::pi / 180.0;

std::vector<Eigen::Vector3d> mesh_m(const Candide3Model& candide) {
  const FaceLandmarkModel model = make_face_landmark_model(candide, load_ibug68_mapping(default_ibug68_mapping_path()));
  const Eigen::VectorXd tau = Eigen::VectorXd::Zero(model.shape_unit_count());
  std::vector<Eigen::Vector3d> v = candide.deformed({});
  for (auto& p : v) p *= model.metres_per_unit(tau, 0.063);
  return v;
}

using testing::pose;
}  // namespace

TEST_CASE("face: the frontal view maps mesh points back to where the camera sees them") {
  const Candide3Model candide = Candide3Model::load(Candide3Model::default_path());
  const std::vector<Eigen::Vector3d> mesh = mesh_m(candide);
  const PinholeCamera camera = PinholeCamera::ardrone2_front();
  FrontalView view(candide.triangles());
  view.set_vertices(mesh);
  const cv::Mat gray(camera.height(), camera.width(), CV_8UC1, cv::Scalar(128));
  const Eigen::Isometry3d T = pose(40, -15, 20, {0.05, -0.02, 0.9});
  const Eigen::Vector2d shift(3, -2);
  REQUIRE(view.render(gray, camera, T, shift, 600.0, cv::Size(240, 240)));
  CHECK(view.image().size() == cv::Size(240, 240));
  double worst_vertex = 0, worst_inside = 0;
  for (const auto& tri : candide.triangles()) {
    for (int v : tri) {
      const Eigen::Vector2d seen = *camera.project(T * mesh[static_cast<std::size_t>(v)]) + shift;
      worst_vertex = std::max(worst_vertex, (view.image_of(view.view_of(mesh[static_cast<std::size_t>(v)])) - seen).norm());
    }
    // A point inside a triangle: piecewise affine against the exact perspective, well under a pixel.
    const Eigen::Vector3d p = (mesh[static_cast<std::size_t>(tri[0])] + mesh[static_cast<std::size_t>(tri[1])] +
                               mesh[static_cast<std::size_t>(tri[2])]) / 3;
    const Eigen::Vector2d seen = *camera.project(T * p) + shift;
    worst_inside = std::max(worst_inside, (view.image_of(view.view_of(p)) - seen).norm());
  }
  // Vertices lie on several triangles' edges (or on the rim); where the view's triangles overlap
  // (two vertices at the same place, the nose tip) the nearer one wins, off by about a pixel.
  CHECK(worst_vertex < 1.5);
  CHECK(worst_inside < 1.5);
}

TEST_CASE("face: the frontal view shows the face as a frontal camera would") {
  // The frontal pose itself: the view is the camera image resampled about the face, upright.
  const Candide3Model candide = Candide3Model::load(Candide3Model::default_path());
  const std::vector<Eigen::Vector3d> mesh = mesh_m(candide);
  const PinholeCamera camera(CameraIntrinsics{640, 360, 570.0, 570.0, 320.0, 180.0});
  cv::Mat gray(camera.height(), camera.width(), CV_8UC1);
  for (int y = 0; y < gray.rows; ++y) {
    for (int x = 0; x < gray.cols; ++x) gray.at<unsigned char>(y, x) = static_cast<unsigned char>((x * 3 + y * 7) % 256);
  }
  FrontalView view(candide.triangles());
  view.set_vertices(mesh);
  const Eigen::Isometry3d T = pose(0, 0, 0, {0, 0, 0.8});
  REQUIRE(view.render(gray, camera, T, Eigen::Vector2d::Zero(), 570.0, cv::Size(201, 201)));
  // View centre (100, 100) = the face origin's pixel (320, 180): the image translated by (220, 80).
  int mismatched = 0;
  for (int y = 60; y < 140; ++y) {
    for (int x = 60; x < 140; ++x) {
      mismatched += std::abs(view.image().at<unsigned char>(y, x) - gray.at<unsigned char>(y + 80, x + 220)) > 2;
    }
  }
  CHECK(mismatched < 5);  // the same camera and pose: the same projection, on and off the mesh
}

TEST_CASE("face: frontal view and landmark weights refuse bad input") {
  const Candide3Model candide = Candide3Model::load(Candide3Model::default_path());
  FrontalView view(candide.triangles());
  const PinholeCamera camera = PinholeCamera::ardrone2_front();
  const cv::Mat gray(camera.height(), camera.width(), CV_8UC1, cv::Scalar(0));
  CHECK_THROWS_AS(view.render(gray, camera, Eigen::Isometry3d::Identity(), {0, 0}, 500, {100, 100}), std::logic_error);
  CHECK_THROWS_AS(view.set_vertices({Eigen::Vector3d::Zero()}), std::invalid_argument);
  view.set_vertices(mesh_m(candide));
  CHECK_THROWS_AS(view.render(cv::Mat(), camera, Eigen::Isometry3d::Identity(), {0, 0}, 500, {100, 100}), std::invalid_argument);
  // A face behind the camera gives no view.
  CHECK_FALSE(view.render(gray, camera, pose(0, 0, 0, {0, 0, -0.5}), {0, 0}, 500, {100, 100}));
  CHECK_THROWS_AS(landmark_noise_iod(5), std::invalid_argument);
  CHECK_THROWS_AS(landmark_noise_iod(60), std::invalid_argument);
}

TEST_CASE("face: landmark weights trust the eyes and nose most and the turned-away side less") {
  const Eigen::VectorXd w = landmark_noise_weights({17, 20, 30, 39, 48, 57});
  CHECK(w(2) == Approx(1.0));
  CHECK(w(3) == Approx(1.0));
  CHECK(w(0) < w(1));  // outer brow end below the rest of the brow
  CHECK(w(1) < w(5));
  CHECK(w(4) < w(5));  // mouth corner below the lips
  Eigen::Matrix3Xd points(3, 3);
  points << -0.05, 0.0, 0.05, 0, 0, 0, 0, 0, 0;
  Eigen::VectorXd weights = Eigen::VectorXd::Ones(3);
  apply_far_side_weights(points, 30 * kDeg, 30 * kDeg, weights);  // subject's right (x < 0) turned away
  CHECK(weights(0) == Approx(0.5));
  CHECK(weights(1) == Approx(1.0));
  CHECK(weights(2) == Approx(1.0));
  weights.setOnes();
  apply_far_side_weights(points, -30 * kDeg, 30 * kDeg, weights);
  CHECK(weights(0) == Approx(1.0));
  CHECK(weights(2) == Approx(0.5));
  weights.setOnes();
  apply_far_side_weights(points, 30 * kDeg, 0, weights);  // off
  CHECK(weights.isApprox(Eigen::VectorXd::Ones(3)));
}
