#pragma once
// Registering a person: their CANDIDE-3 shape fitted from one frontal picture taken with the
// estimator's camera. A picture with no face, several faces, or a face not frontal enough is refused
// with that reason.
#include <opencv2/core.hpp>
#include <stdexcept>
#include <string>

#include "localization/face/face_pose_estimator.hpp"

namespace labo::face {

class RegistrationError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Throws RegistrationError ("no face in the frontal picture", "N faces ...", "not frontal: yaw ...",
// "picture is WxH, the camera's is ...").
PersonShape register_person(FacePoseEstimator& estimator, const cv::Mat& gray, const std::string& name,
                            double interpupillary_distance_m);

}  // namespace labo::face
