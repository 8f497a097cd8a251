#include "localization/face/person_registration.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "localization/face/multi_view_landmarks.hpp"
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

namespace labo::face {

namespace {

constexpr double kDegPerRad = 180.0 / std::numbers::pi;
constexpr double kTurnFramePeriodS = 1.0 / 30.0;  // the frames' timestamps: the tracker's motion limits

struct TrackedTurns {
  std::vector<LandmarkView> views;
  double yaw_min = 1e9, yaw_max = -1e9, pitch_min = 1e9, pitch_max = -1e9;  // degrees
};

TrackedTurns track_turns(FacePoseEstimator& estimator, const std::vector<cv::Mat>& frames) {
  TrackedTurns turns;
  for (std::size_t i = 0; i < frames.size(); ++i) {
    if (frames[i].empty() || frames[i].type() != CV_8UC1) {
      throw RegistrationError("turn frame " + std::to_string(i) + ": expected a non-empty 8-bit grey image");
    }
    const FaceResult r = estimator.process(frames[i], static_cast<double>(i) * kTurnFramePeriodS);
    if (r.reason == FaceLostReason::BadImage) {
      throw RegistrationError("turn frame " + std::to_string(i) + ": not the camera's size");
    }
    if (!r.tracking()) continue;
    turns.views.push_back({estimator.ideal_pixels(r.landmarks), r.T_cam_face});
    turns.yaw_min = std::min(turns.yaw_min, r.angles.yaw * kDegPerRad);
    turns.yaw_max = std::max(turns.yaw_max, r.angles.yaw * kDegPerRad);
    turns.pitch_min = std::min(turns.pitch_min, r.angles.pitch * kDegPerRad);
    turns.pitch_max = std::max(turns.pitch_max, r.angles.pitch * kDegPerRad);
  }
  return turns;
}

std::string one_decimal(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f", v);
  return text;
}

void check_turns(const TrackedTurns& turns, std::size_t frames, const TurnRequirements& req) {
  if (static_cast<int>(turns.views.size()) < req.min_views) {
    throw RegistrationError("turn frames refused: the face was tracked in " + std::to_string(turns.views.size()) +
                            " of " + std::to_string(frames) + " frames, expected at least " +
                            std::to_string(req.min_views));
  }
  const double yaw_span = turns.yaw_max - turns.yaw_min;
  const double pitch_span = turns.pitch_max - turns.pitch_min;
  if (yaw_span < req.min_yaw_span_deg || pitch_span < req.min_pitch_span_deg) {
    throw RegistrationError("turn frames refused: the head turned " + one_decimal(yaw_span) + "° in yaw and " +
                            one_decimal(pitch_span) + "° in pitch, expected at least " +
                            one_decimal(req.min_yaw_span_deg) + "° and " + one_decimal(req.min_pitch_span_deg) +
                            "° (turn left, right, up and down slowly)");
  }
}

}  // namespace

TurnRefinement refine_person_from_turns(FacePoseEstimator& estimator, const PersonShape& person,
                                        const std::vector<cv::Mat>& frames, const TurnRequirements& requirements) {
  estimator.set_person(person, true);
  estimator.reset();
  const TrackedTurns turns = track_turns(estimator, frames);
  check_turns(turns, frames.size(), requirements);

  const FaceLandmarkModel& model = estimator.model();
  const Eigen::Matrix3Xd mapped = model.points_m(person.shape_params, person.interpupillary_distance_m);
  Eigen::Matrix3Xd start = mapped;
  if (person.landmark_offsets_m.cols() == mapped.cols()) start += person.landmark_offsets_m;
  const MultiViewFit fit =
      refine_landmarks_from_views(model, start, turns.views, estimator.ideal_camera(), person.interpupillary_distance_m);

  TurnRefinement out;
  out.person = person;
  out.person.landmark_offsets_m = fit.points_m - mapped;
  for (Eigen::Index j = 0; j < mapped.cols(); ++j) {
    if (out.person.landmark_offsets_m.col(j).norm() > requirements.max_offset_m) out.person.landmark_offsets_m.col(j).setZero();
  }
  out.views = static_cast<int>(turns.views.size());
  out.yaw_span_deg = turns.yaw_max - turns.yaw_min;
  out.pitch_span_deg = turns.pitch_max - turns.pitch_min;
  out.rms_before_px = fit.rms_before_px;
  out.rms_after_px = fit.rms_after_px;
  estimator.set_person(out.person, true);
  estimator.reset();
  return out;
}

}  // namespace labo::face
