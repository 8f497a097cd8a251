#include "localization/face/person_registration.hpp"

#include <cmath>
#include <numbers>

#include "localization/face/surface_landmarks.hpp"

namespace labo::face {

namespace {
// A landmark whose surface point is farther than this from its mapped point keeps the mapped point
// (a ray past the mesh's rim, or a landmark detected off the face).
constexpr double kMaxSurfaceOffsetM = 0.015;
}  // namespace

PersonShape register_person(FacePoseEstimator& estimator, const cv::Mat& gray, const std::string& name,
                            double interpupillary_distance_m) {
  validate_person_name(name);
  if (gray.empty() || gray.type() != CV_8UC1) throw RegistrationError("frontal picture: expected a non-empty 8-bit grey image");
  const IdealPinhole cam = estimator.ideal_camera();
  const auto faces = estimator.find_faces(gray);
  if (faces.empty()) throw RegistrationError("frontal picture refused: no face found");
  if (faces.size() > 1) {
    throw RegistrationError("frontal picture refused: " + std::to_string(faces.size()) + " faces found, expected one");
  }
  const Eigen::Matrix2Xd landmarks = estimator.landmarks_in(gray, faces.front().box);
  const ShapeFit fit = fit_shape(estimator.model(), estimator.ideal_pixels(landmarks), cam, interpupillary_distance_m,
                                 estimator.config().shape_fit);
  const HeadAngles a = head_angles(fit.T_cam_face.linear());
  const double limit = estimator.config().frontal_max_angle_rad;
  if (std::abs(a.yaw) > limit || std::abs(a.pitch) > limit) {
    const double deg = 180.0 / std::numbers::pi;
    throw RegistrationError("frontal picture refused: head turned (yaw " + std::to_string(a.yaw * deg) + "°, pitch " +
                            std::to_string(a.pitch * deg) + "°), expected within " + std::to_string(limit * deg) + "°");
  }
  PersonShape person;
  person.name = name;
  person.interpupillary_distance_m = interpupillary_distance_m;
  person.shape_params = fit.shape_params;
  person.fit_rms_px = fit.rms_px;
  if (estimator.config().surface_landmarks) {
    person.landmark_offsets_m =
        surface_landmark_offsets(Candide3Model::load(estimator.config().model), estimator.model(), fit.shape_params,
                                 interpupillary_distance_m, fit.T_cam_face, estimator.ideal_pixels(landmarks), cam,
                                 kMaxSurfaceOffsetM);
  }
  return person;
}

}  // namespace labo::face
