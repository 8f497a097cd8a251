#include "localization/face/person_registration.hpp"

#include <cmath>
#include <numbers>

#include "localization/face/depth_refinement.hpp"
#include "localization/face/face_geometry.hpp"
#include "localization/face/portrait.hpp"
#include "localization/face/surface_landmarks.hpp"

namespace labo::face {

namespace {
// A landmark whose surface point is farther than this from its mapped point keeps the mapped point
// (a ray past the mesh's rim, or a landmark detected off the face).
constexpr double kMaxSurfaceOffsetM = 0.015;

}  // namespace

PersonShape register_person(FacePoseEstimator& estimator, const cv::Mat& gray, const std::string& name,
                            double interpupillary_distance_m) {
  return register_person(estimator, std::vector<cv::Mat>{gray}, name, interpupillary_distance_m);
}

PersonShape register_person(FacePoseEstimator& estimator, const std::vector<cv::Mat>& pictures, const std::string& name,
                            double interpupillary_distance_m) {
  validate_person_name(name);
  if (pictures.empty()) throw RegistrationError("frontal pictures: none given");
  const IdealPinhole cam = estimator.ideal_camera();
  Eigen::Matrix2Xd landmarks = Eigen::Matrix2Xd::Zero(2, 68);
  std::vector<cv::Rect2d> boxes;
  const PortraitLimits limits = portrait_limits(estimator.config());
  const auto which = [&](std::size_t k) {
    return pictures.size() > 1 ? "frontal picture " + std::to_string(k) : std::string("frontal picture");
  };
  for (std::size_t k = 0; k < pictures.size(); ++k) {
    const PortraitFace face = find_portrait_face(estimator, pictures[k], limits);
    if (!face.serves()) throw RegistrationError(which(k) + " refused: " + face.reason);
    boxes.push_back(face.box);
    landmarks += face.landmarks / static_cast<double>(pictures.size());
  }
  const ShapeFit fit = fit_shape(estimator.model(), estimator.ideal_pixels(landmarks), cam, interpupillary_distance_m,
                                 estimator.config().shape_fit);
  PortraitFace averaged;
  check_portrait_angles(averaged, head_angles(fit.T_cam_face.linear()), limits);
  if (!averaged.serves()) {
    throw RegistrationError(std::string(pictures.size() > 1 ? "frontal pictures" : "frontal picture") +
                            " refused: " + averaged.reason);
  }
  PersonShape person;
  person.name = name;
  person.interpupillary_distance_m = interpupillary_distance_m;
  person.shape_params = fit.shape_params;
  person.fit_rms_px = fit.rms_px;
  if (estimator.config().surface_landmarks) {
    const Candide3Model candide = Candide3Model::load(estimator.config().model);
    const auto offsets_from = [&](const Eigen::Matrix2Xd& seen) {
      return surface_landmark_offsets(candide, estimator.model(), fit.shape_params, interpupillary_distance_m,
                                      fit.T_cam_face, estimator.ideal_pixels(seen), cam, kMaxSurfaceOffsetM);
    };
    person.landmark_offsets_m = offsets_from(landmarks);
    if (estimator.config().frontal_view) {
      // Tracking finds its landmarks on the frontal view, not on the detector's crop, and the
      // predictor does not put them at quite the same points of the face in the two (on the benchmark's
      // frontal registration frames the view's landmarks pose 0.6-1.5° lower in pitch with the crop's
      // points). The person's points are where the *view's* landmarks meet the mesh, at the fitted
      // pose: a frontal head is then tracked at the registration's pose, not that pose plus the
      // difference between the two ways of finding landmarks (docs/face.md, "The pitch offset").
      const PersonShape previous = estimator.person();
      const bool previous_registered = estimator.person_registered();
      estimator.set_person(person, false);  // the view is made through this person's mesh
      Eigen::Matrix2Xd seen = Eigen::Matrix2Xd::Zero(2, 68);
      bool all_seen = true;
      for (std::size_t k = 0; k < pictures.size() && all_seen; ++k) {
        const auto view = estimator.landmarks_in_frontal_view(pictures[k], boxes[k], fit.T_cam_face);
        if (view) seen += *view / static_cast<double>(pictures.size());
        all_seen = view.has_value();
      }
      estimator.set_person(previous, previous_registered);
      estimator.reset();
      if (all_seen) person.landmark_offsets_m = offsets_from(seen);
    }
  }
  // The pictures show the head upright (they are asked for so): the person's frame is the one in
  // which the fitted pose has no roll. The model's fit to one face's landmarks can hold it a degree or
  // two rolled (a face's own asymmetry), and as the points' x and y come from the landmarks' pixels,
  // every tracked pose would carry that roll. Yaw and pitch are left to the fit: the points' depths
  // come from the fitted mesh along the landmarks' rays, which takes a fitted yaw or pitch back out
  // on most faces (docs/face.md, "Upright by registration").
  const HeadAngles fitted = head_angles(fit.T_cam_face.linear());
  person.R_frontal_model = head_rotation({}).transpose() * head_rotation({0, 0, fitted.roll});
  return person;
}

}  // namespace labo::face

namespace labo::face {

namespace {

constexpr double kDegPerRad = 180.0 / std::numbers::pi;
constexpr double kTurnFramePeriodS = 1.0 / 30.0;  // the frames' timestamps: the tracker's motion limits

struct TrackedTurns {
  std::vector<DepthView> views;
  int frames = 0;
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
    ++turns.frames;
    if (r.tracking()) turns.views.push_back({estimator.ideal_pixels(r.landmarks), r.T_cam_face});
  }
  return turns;
}

}  // namespace

TurnRefinement refine_person_from_turns(FacePoseEstimator& estimator, const PersonShape& person,
                                        const std::vector<cv::Mat>& frames) {
  estimator.set_person(person, true);
  estimator.reset();
  const TrackedTurns turns = track_turns(estimator, frames);
  estimator.reset();
  const FaceLandmarkModel& model = estimator.model();
  const Eigen::Matrix3Xd mapped = model.points_m(person.shape_params, person.interpupillary_distance_m);
  // In the person's frontal frame, where the tracked views' poses are.
  Eigen::Matrix3Xd points = person_landmarks_m(person, mapped);
  const DepthRefinement fit = refine_depth_from_views(model, points, turns.views, estimator.ideal_camera(),
                                                      estimator.config().depth_refinement);
  if (!fit.accepted) {
    throw RegistrationError("turn frames: " + fit.reason + " (the face was tracked in " +
                            std::to_string(turns.views.size()) + " of " + std::to_string(turns.frames) + " frames)");
  }
  TurnRefinement out;
  out.person = person;
  points.row(2) += fit.depth_change_m.transpose();
  out.person.landmark_offsets_m = person.R_frontal_model.transpose() * points - mapped;
  out.views = fit.views;
  out.yaw_span_deg = fit.yaw_span_rad * kDegPerRad;
  out.pitch_span_deg = fit.pitch_span_rad * kDegPerRad;
  out.rms_before_px = fit.rms_before_px;
  out.rms_after_px = fit.rms_after_px;
  out.depth_change_m = fit.depth_change_m;
  estimator.set_person(out.person, true);
  return out;
}

}  // namespace labo::face
