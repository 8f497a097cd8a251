#pragma once
// Whether a picture can serve as a person's portrait: a registration picture (`face register`) or the
// photograph the simulated teacher's head is textured with. It must show exactly one face, large
// enough that its shape is more than a few pixels, wholly inside the picture and near frontal. A
// picture that cannot serve is refused with the reason, never registered or textured silently wrong.
#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <string>
#include <string_view>

#include "localization/face/face_geometry.hpp"
#include "localization/face/face_pose_estimator.hpp"

namespace labo::face {

enum class PortraitRefusal { None, NoFace, SeveralFaces, TooSmall, CutByBorder, Turned };
std::string_view to_string(PortraitRefusal refusal);

struct PortraitLimits {
  double min_interocular_px = 20;  // eye centres apart (FaceConfig::portrait_min_interocular_px)
  double max_angle_rad = 0.26;     // |yaw|, |pitch| of the fitted head (FaceConfig::frontal_max_angle_rad)
  double border_margin_px = 2;     // a rigid landmark closer to the border: the face is cut
  // Another detection counts as a second person when its box side and its detector score are at least
  // these fractions of the best face's; the others are background (a rendered astronaut head gives a
  // box larger than the face at a twentieth of its score).
  double other_face_min_side = 0.5;
  double other_face_min_score = 0.25;
};
PortraitLimits portrait_limits(const FaceConfig& config);

struct PortraitFace {
  PortraitRefusal refusal = PortraitRefusal::None;
  std::string reason;        // what was wrong and what was expected; "" when the picture serves
  cv::Rect2d box;            // the detector's box of the face (its best)
  Eigen::Matrix2Xd landmarks;  // its 68 landmarks, picture pixels (empty when no face)
  double interocular_px = 0;
  bool serves() const { return refusal == PortraitRefusal::None; }
};

// The picture's face with every check that needs no pose: one face, interocular distance, border.
PortraitFace find_portrait_face(FacePoseEstimator& estimator, const cv::Mat& gray, const PortraitLimits& limits);

// The check that needs the pose fitted to the landmarks: refuses `face` (sets refusal and reason) when
// the head is turned beyond the limit.
void check_portrait_angles(PortraitFace& face, const HeadAngles& angles, const PortraitLimits& limits);

// The eye centres' distance of 68 landmarks (iBUG order), pixels.
double interocular_px(const Eigen::Matrix2Xd& landmarks68);

}  // namespace labo::face
