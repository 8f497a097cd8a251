#pragma once
// Registering a person: their CANDIDE-3 shape fitted from one frontal picture taken with the
// estimator's camera. A picture with no face, several faces, or a face not frontal enough is refused
// with that reason.
#include <opencv2/core.hpp>
#include <stdexcept>
#include <string>
#include <vector>

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
// The same from several pictures of the person holding still (e.g. consecutive frames): each must
// hold exactly one face; the landmarks are averaged over them before the fit, so the picture's
// detection noise, which the person's landmarks keep (surface_landmarks), is averaged down. The
// reason of a refusal names the picture's index. With surface_landmarks and frontal_view both on, the
// person's points are where the landmarks found on the frontal view (tracking's way) at the fitted
// pose meet the mesh, averaged over the pictures; the shape is fitted to the crop's landmarks. The
// estimator keeps its person; its track is reset.
PersonShape register_person(FacePoseEstimator& estimator, const std::vector<cv::Mat>& pictures, const std::string& name,
                            double interpupillary_distance_m);

struct TurnRefinement {
  PersonShape person;  // with the refined landmark depths in landmark_offsets_m
  int views = 0;       // frames tracked and used
  double yaw_span_deg = 0, pitch_span_deg = 0;  // of the tracked head, max - min
  double rms_before_px = 0, rms_after_px = 0;   // landmark fit over the views, before and after
  Eigen::VectorXd depth_change_m;               // per model landmark
};

// Refines `person` (registered from a frontal picture) with frames of the same person slowly turning
// their head left, right, up and down in front of the same camera: the depth of the landmarks, which
// one frontal picture cannot see and on which the pitch and distance of every later pose depend, is
// adjusted jointly with the frames' poses (depth_refinement.hpp, `estimator.config().depth_refinement`).
// `estimator` tracks the frames with `person` and is left set to the refined person. Throws
// RegistrationError, leaving the estimator set to `person` unchanged, when a frame is not the camera's
// size or the refinement is refused (too few frames tracked, too little turn, a fit that diverges or
// an implausible result: the reason says which, with what was seen and what is needed).
TurnRefinement refine_person_from_turns(FacePoseEstimator& estimator, const PersonShape& person,
                                        const std::vector<cv::Mat>& frames);

}  // namespace labo::face
