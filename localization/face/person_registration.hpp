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

struct TurnRefinement {
  PersonShape person;  // with landmark_offsets_m from the turning head
  int views = 0;       // frames tracked and used
  double yaw_span_deg = 0, pitch_span_deg = 0;  // of the tracked head, max - min
  double rms_before_px = 0, rms_after_px = 0;   // landmark fit over the views, model before and after
};

struct TurnRequirements {
  int min_views = 10;
  double min_yaw_span_deg = 20;    // e.g. the head turned 10 degrees left and 10 right
  double min_pitch_span_deg = 12;  // and nodded 6 up and 6 down
  double max_offset_m = 0.02;      // a landmark farther than this from its model point keeps the model's
};

// Refines `person` (registered from a frontal picture) with frames of the same person slowly turning
// their head left, right, up and down in front of the same camera (multi_view_landmarks.hpp): the
// depth of each landmark, which one frontal picture cannot see, is what the pitch and distance of
// every later pose depend on. `estimator` tracks the frames with `person`, is left set to the refined
// person. Throws RegistrationError when too few frames are tracked or the head turned too little
// (naming what was seen and what is needed), or a frame is not the camera's size.
TurnRefinement refine_person_from_turns(FacePoseEstimator& estimator, const PersonShape& person,
                                        const std::vector<cv::Mat>& frames, const TurnRequirements& requirements = {});

}  // namespace labo::face
