#include <catch2/catch.hpp>

#include "core/camera_model.hpp"
#include "localization/fusion/face_front_end.hpp"
#include "localization/fusion/lab_pipelines.hpp"

// The person face-follow follows, chosen while the vision worker may be running the face front-end:
// the shape waits in the front-end and is taken before its next frame (the estimator is only ever
// touched by the thread that runs process()).

using namespace labo;

TEST_CASE("face-follow: the person chosen through the pipelines is the face front-end's from its next frame") {
  face::FaceConfig config = face::default_face_config();
  auto estimator = std::make_unique<face::FacePoseEstimator>(config, PinholeCamera::ardrone2_front());
  const int units = estimator->model().shape_unit_count();
  auto front_end = std::make_unique<fusion::FaceFrontEnd>(std::move(estimator));
  fusion::FaceFrontEnd& fe = *front_end;
  fusion::LabPipelines pipelines(fusion::LabGeometry{}, estimation::EstimatorConfig{}, VisionThresholds{});
  face::PersonShape ada{"ada", 0.061, Eigen::VectorXd::Constant(units, 0.2), 0.8, {}};
  CHECK_FALSE(pipelines.follow_person(ada));  // no face front-end yet
  pipelines.set_face_front_end(std::move(front_end));
  REQUIRE(pipelines.follow_person(ada));
  CHECK(fe.estimator().person().name == "generic");  // not before the front-end's next frame
  const cv::Mat empty(360, 640, CV_8UC1, cv::Scalar(120));
  fe.process(empty, 0.0, std::nullopt);
  CHECK(fe.estimator().person().name == "ada");
  CHECK(fe.estimator().person_registered());
  CHECK(fe.estimator().person().interpupillary_distance_m == 0.061);
  fe.process(empty, 1.0 / 30, std::nullopt);  // taken once
  CHECK(fe.estimator().person().name == "ada");
}
