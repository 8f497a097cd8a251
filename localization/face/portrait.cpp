#include "localization/face/portrait.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

namespace labo::face {

namespace {

constexpr double kDegPerRad = 180.0 / std::numbers::pi;

std::string fixed(double v, int decimals) {
  char text[32];
  std::snprintf(text, sizeof text, "%.*f", decimals, v);
  return text;
}

double side(const cv::Rect2d& box) { return std::sqrt(box.area()); }

PortraitFace refused(PortraitFace face, PortraitRefusal refusal, std::string reason) {
  face.refusal = refusal;
  face.reason = std::move(reason);
  return face;
}

}  // namespace

std::string_view to_string(PortraitRefusal refusal) {
  switch (refusal) {
    case PortraitRefusal::None: return "serves";
    case PortraitRefusal::NoFace: return "no face";
    case PortraitRefusal::SeveralFaces: return "several faces";
    case PortraitRefusal::TooSmall: return "face too small";
    case PortraitRefusal::CutByBorder: return "face cut by the border";
    case PortraitRefusal::Turned: return "head turned too far";
  }
  return "?";
}

PortraitLimits portrait_limits(const FaceConfig& config) {
  PortraitLimits limits;
  limits.min_interocular_px = config.portrait_min_interocular_px;
  limits.max_angle_rad = config.frontal_max_angle_rad;
  return limits;
}

double interocular_px(const Eigen::Matrix2Xd& landmarks68) {
  const Eigen::Vector2d right = landmarks68.middleCols(36, 6).rowwise().mean();
  const Eigen::Vector2d left = landmarks68.middleCols(42, 6).rowwise().mean();
  return (left - right).norm();
}

PortraitFace find_portrait_face(FacePoseEstimator& estimator, const cv::Mat& gray, const PortraitLimits& limits) {
  PortraitFace face;
  if (gray.empty() || gray.type() != CV_8UC1) {
    return refused(face, PortraitRefusal::NoFace, "expected a non-empty 8-bit grey picture");
  }
  const auto faces = estimator.find_faces(gray);
  if (faces.empty()) return refused(face, PortraitRefusal::NoFace, "no face found");
  // The detector's best face (boxes come best first); another counts as a second person when it is
  // of a comparable size and confidence.
  face.box = faces.front().box;
  const double best_score = faces.front().score;
  const auto people = std::count_if(faces.begin(), faces.end(), [&](const FaceBox& f) {
    return side(f.box) >= limits.other_face_min_side * side(face.box) && f.score >= limits.other_face_min_score * best_score;
  });
  if (people > 1) {
    return refused(face, PortraitRefusal::SeveralFaces, std::to_string(people) + " faces found, expected one person");
  }
  face.box = estimator.settled_box(gray, face.box);
  face.landmarks = estimator.landmarks_in(gray, face.box);
  face.interocular_px = interocular_px(face.landmarks);
  for (int id : rigid_landmark_ids()) {
    const Eigen::Vector2d p = face.landmarks.col(id);
    const double m = limits.border_margin_px;
    if (p.x() < m || p.y() < m || p.x() > gray.cols - 1 - m || p.y() > gray.rows - 1 - m) {
      return refused(face, PortraitRefusal::CutByBorder, "the face is cut by the picture's border, expected it whole");
    }
  }
  if (face.interocular_px < limits.min_interocular_px) {
    return refused(face, PortraitRefusal::TooSmall,
                   "face too small: eye centres " + fixed(face.interocular_px, 1) + " px apart, expected at least " +
                       fixed(limits.min_interocular_px, 0) + " px");
  }
  return face;
}

void check_portrait_angles(PortraitFace& face, const HeadAngles& angles, const PortraitLimits& limits) {
  if (!face.serves()) return;
  if (std::abs(angles.yaw) <= limits.max_angle_rad && std::abs(angles.pitch) <= limits.max_angle_rad) return;
  face.refusal = PortraitRefusal::Turned;
  face.reason = "head turned too far (yaw " + fixed(angles.yaw * kDegPerRad, 1) + "°, pitch " +
                fixed(angles.pitch * kDegPerRad, 1) + "°), expected within " + fixed(limits.max_angle_rad * kDegPerRad, 0) +
                "° of frontal";
}

}  // namespace labo::face
