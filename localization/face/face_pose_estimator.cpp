#include "localization/face/face_pose_estimator.hpp"
#include "localization/face/portrait.hpp"

#include "core/cpu_time.hpp"
#include "localization/face/landmark_weights.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <span>
#include <utility>

namespace labo::face {

namespace {

// Stage durations for the benchmark and the UI, in CPU time of the process (on a shared machine wall
// time measures the neighbours); they never influence a result.
double ms_since(double start_cpu_s) { return (process_cpu_seconds() - start_cpu_s) * 1000.0; }

FaceLandmarkModel load_model(const FaceConfig& config) {
  const Candide3Model candide = Candide3Model::load(config.model);
  return make_face_landmark_model(candide, load_ibug68_mapping(config.mapping, static_cast<int>(candide.vertices().size())));
}

// Centroid and RMS spread of the rigid landmarks (17-59).
std::pair<Eigen::Vector2d, double> centroid_and_spread(const Eigen::Matrix2Xd& lm) {
  const Eigen::Matrix2Xd rigid = lm.middleCols(17, 43);
  const Eigen::Vector2d c = rigid.rowwise().mean();
  const double spread = std::sqrt((rigid.colwise() - c).colwise().squaredNorm().mean());
  return {c, std::max(spread, 1e-6)};
}

// The eye line's angle in the image (0 upright, positive clockwise as the image's y points down).
double eye_line_angle(const Eigen::Matrix2Xd& lm) {
  const Eigen::Vector2d d = lm.middleCols(42, 6).rowwise().mean() - lm.middleCols(36, 6).rowwise().mean();
  return std::atan2(d.y(), d.x());
}

Eigen::Matrix2d rotation(double angle) { return Eigen::Rotation2Dd(angle).toRotationMatrix(); }

cv::Point2d centre(const cv::Rect2d& r) { return {r.x + r.width / 2, r.y + r.height / 2}; }

// A track's first frame: its view passes stop when the pose moves less than this.
constexpr double kStartPassMovedM = 0.002;
constexpr double kStartPassTurnedRad = 0.2 * std::numbers::pi / 180.0;
// Its mirrored far side: fully mirrored 15° of yaw beyond start_mirror_yaw; in the face's plane, from
// 20 mm beside the midline (beyond the nose's wings, ~18 mm) to 35 mm (the far eye's middle).
constexpr double kMirrorRampRad = 15.0 * std::numbers::pi / 180.0;
constexpr double kMirrorStartM = 0.020;
constexpr double kMirrorWidthM = 0.015;

}  // namespace

std::string_view to_string(FaceState state) { return state == FaceState::Tracking ? "tracking" : "lost"; }

std::string_view to_string(FaceLostReason reason) {
  switch (reason) {
    case FaceLostReason::None: return "none";
    case FaceLostReason::BadImage: return "bad image (empty, not 8-bit grey, or not the camera's size)";
    case FaceLostReason::NoFace: return "no face found";
    case FaceLostReason::SeveralFaces: return "several faces, none the teacher or near the last track";
    case FaceLostReason::CutByBorder: return "face cut by the image border";
    case FaceLostReason::TooSmall: return "face too small";
    case FaceLostReason::BeyondProfile: return "head turned beyond the usable profile";
    case FaceLostReason::InconsistentLandmarks: return "landmarks do not fit the face model";
    case FaceLostReason::NoPose: return "no pose in front of the camera";
    case FaceLostReason::ImplausibleDistance: return "implausible distance";
    case FaceLostReason::ImplausibleMotion: return "implausible motion between frames";
    case FaceLostReason::NotConfirmed: return "detector no longer confirms the tracked face";
    case FaceLostReason::TurnedAtStart: return "head too turned to start a track";
  }
  return "unknown";
}

FacePoseEstimator::FacePoseEstimator(const FaceConfig& config, const PinholeCamera& camera)
    : FacePoseEstimator(config, camera, load_model(config)) {
  if (!config_.teacher.empty()) {
    set_person(load_person_shape(person_shape_path(config_.people_dir, config_.teacher), model_.shape_unit_count()), true);
  }
}

FacePoseEstimator::FacePoseEstimator(const FaceConfig& config, const PinholeCamera& camera, FaceLandmarkModel model)
    : config_(config),
      camera_(camera),
      model_(std::move(model)),
      detector_(config.detector),
      landmark_detector_(config.shape_predictor),
      solver_(config.solver) {
  if (config_.landmark_noise_weights) noise_weights_ = landmark_noise_weights(model_.landmark_ids());
  if (config_.frontal_view) {
    candide_ = Candide3Model::load(config_.model);
    frontal_.emplace(candide_->triangles());
  }
  PersonShape generic;
  generic.name = "generic";
  generic.interpupillary_distance_m = config_.interpupillary_distance_m;
  generic.shape_params = Eigen::VectorXd::Zero(model_.shape_unit_count());
  set_person(generic, false);
  problem_.camera = ideal_camera();
}

void FacePoseEstimator::set_person(const PersonShape& person, bool registered) {
  if (person.shape_params.size() != model_.shape_unit_count()) {
    throw std::invalid_argument("face: person '" + person.name + "' has " + std::to_string(person.shape_params.size()) +
                                " shape parameters, the model " + std::to_string(model_.shape_unit_count()));
  }
  person_ = person;
  person_registered_ = registered;
  if (person.landmark_offsets_m.cols() > 0 && person.landmark_offsets_m.cols() != model_.size()) {
    throw std::invalid_argument("face: person '" + person.name + "' has " + std::to_string(person.landmark_offsets_m.cols()) +
                                " landmark offsets, the model " + std::to_string(model_.size()) + " landmarks");
  }
  // Everything in the person's frontal frame: the landmarks the pose is solved on and the mesh the
  // frontal view is made through.
  points_face_ = person_landmarks_m(person, model_.points_m(person.shape_params, person.interpupillary_distance_m));
  if (frontal_) {
    const Eigen::VectorXd& tau = person.shape_params;
    std::vector<Eigen::Vector3d> mesh = candide_->deformed(std::span<const double>(tau.data(), static_cast<std::size_t>(tau.size())));
    const double metres_per_unit = model_.metres_per_unit(tau, person.interpupillary_distance_m);
    for (auto& v : mesh) v = person.R_frontal_model * (v * metres_per_unit);
    frontal_->set_vertices(std::move(mesh));
  }
  solver_.reset();
}

void FacePoseEstimator::reset() {
  search_hint_.reset();
  last_landmarks_.reset();
  last_pose_.reset();
  detector_misses_ = 0;
  landmark_velocity_px_.reset();
  last_box_.reset();
  frames_since_detection_ = 0;
  lost_frames_ = 0;
  // The full-frame search starts again at its first scale, so that what follows a reset does not
  // depend on how many frames were searched before it (test: face: after a reset the estimator
  // starts a track as a new one does).
  lost_search_cycle_ = 0;
  solver_.reset();
}

IdealPinhole FacePoseEstimator::ideal_camera() const {
  const auto& k = camera_.intrinsics();
  return {k.fx, k.fy, k.cx, k.cy};
}

Eigen::Matrix2Xd FacePoseEstimator::ideal_pixels(const Eigen::Matrix2Xd& lm) const {
  const auto& k = camera_.intrinsics();
  Eigen::Matrix2Xd out(2, model_.size());
  for (int i = 0; i < model_.size(); ++i) {
    const Eigen::Index c = model_.landmark_ids()[static_cast<std::size_t>(i)];
    const Eigen::Vector2d n = camera_.undistort({(lm(0, c) - k.cx) / k.fx, (lm(1, c) - k.cy) / k.fy});
    out.col(i) << k.fx * n.x() + k.cx, k.fy * n.y() + k.cy;
  }
  return out;
}

double FacePoseEstimator::interocular_px(const Eigen::Matrix2Xd& lm) const { return face::interocular_px(lm); }

void FacePoseEstimator::remember_box_relation(const cv::Rect2d& box, const Eigen::Matrix2Xd& lm, double distance_m) {
  const auto [c, spread] = centroid_and_spread(lm);
  const cv::Point2d bc = centre(box);
  const double side = std::sqrt(box.width * box.height);
  // In the face's upright frame, so that it turns with the head's roll.
  box_offset_ = rotation(-eye_line_angle(lm)) * Eigen::Vector2d(bc.x - c.x(), bc.y - c.y()) / side;
  box_side_m_ = side * distance_m / camera_.intrinsics().fx;
}

cv::Rect2d FacePoseEstimator::box_from_landmarks(const Eigen::Matrix2Xd& lm) const {
  const auto [c, spread] = centroid_and_spread(lm);
  const double side = last_pose_ ? box_side_m_ * camera_.intrinsics().fx / last_pose_->translation().z() : 2.6 * spread;
  const Eigen::Vector2d bc = c + rotation(eye_line_angle(lm)) * box_offset_ * side;
  return {bc.x() - side / 2, bc.y() - side / 2, side, side};
}

std::vector<FaceBox> FacePoseEstimator::find_faces(const cv::Mat& gray) {
  for (double scale : {1.0, 2.0}) {
    auto boxes = detector_.detect_full(gray, scale);
    if (!boxes.empty()) return boxes;
  }
  return {};
}

Eigen::Matrix2Xd FacePoseEstimator::landmarks_in(const cv::Mat& gray, const cv::Rect2d& box) {
  Eigen::Matrix2Xd lm;
  landmark_detector_.detect(gray, box, lm);
  return lm;
}

cv::Rect2d FacePoseEstimator::settled_box(const cv::Mat& gray, const cv::Rect2d& box) {
  // One step: a second moved the gallery's figures by less than their seed-to-seed spread.
  landmark_detector_.detect(gray, box, settle_lm_);
  const cv::Rect2d own = landmark_detector_.box_for(settle_lm_);
  // Landmarks that collapsed (or left the picture) give no box to run the predictor in again.
  const bool usable = own.width > 0 && (own & cv::Rect2d(0, 0, gray.cols, gray.rows)).area() > 0;
  return usable ? own : box;
}

std::optional<Eigen::Matrix2Xd> FacePoseEstimator::landmarks_in_frontal_view(const cv::Mat& gray, const cv::Rect2d& box,
                                                                             const Eigen::Isometry3d& T_cam_face) {
  if (!frontal_) return std::nullopt;
  // The view's box is placed by the detector box's relation to the crop's landmarks, as on a track's
  // first frame.
  remember_box_relation(box, landmarks_in(gray, box), T_cam_face.translation().z());
  Eigen::Matrix2Xd lm;
  if (!detect_in_frontal_view(gray, Candidate{box, true}, T_cam_face, Eigen::Vector2d::Zero(), lm)) return std::nullopt;
  return lm;
}

std::optional<FacePoseEstimator::Candidate> FacePoseEstimator::select_among(const cv::Mat& gray,
                                                                             const std::vector<FaceBox>& boxes,
                                                                             FaceResult& result) {
  if (boxes.size() == 1) return Candidate{boxes.front().box, true};
  if (last_box_) {
    const cv::Point2d last = centre(*last_box_);
    const auto nearest = std::min_element(boxes.begin(), boxes.end(), [&](const FaceBox& a, const FaceBox& b) {
      return cv::norm(centre(a.box) - last) < cv::norm(centre(b.box) - last);
    });
    if (cv::norm(centre(nearest->box) - last) < 1.5 * std::max(last_box_->width, last_box_->height)) {
      return Candidate{nearest->box, true};
    }
  }
  if (person_registered_) {
    // The registered teacher: the face whose landmarks fit their shape clearly best.
    double best = std::numeric_limits<double>::infinity(), second = best;
    std::optional<cv::Rect2d> best_box;
    for (const auto& b : boxes) {
      const Eigen::Matrix2Xd lm = landmarks_in(gray, b.box);
      const auto refined = fit_pose(lm);
      const double score = refined ? refined->rms_px / std::max(interocular_px(lm), 1.0) : best;
      if (score < best) {
        second = best;
        best = score;
        best_box = b.box;
      } else {
        second = std::min(second, score);
      }
    }
    if (best_box && best < config_.limits.max_rms_per_interocular && best < 0.8 * second) {
      return Candidate{*best_box, true};
    }
  }
  result.reason = FaceLostReason::SeveralFaces;
  return std::nullopt;
}

std::optional<FacePoseEstimator::Candidate> FacePoseEstimator::choose_box(const cv::Mat& gray, FaceResult& result) {
  result.faces_found = -1;
  const bool landmark_box_ready = config_.box_from_landmarks && last_landmarks_.has_value();
  if (landmark_box_ready && frames_since_detection_ + 1 < config_.redetect_every_n_frames) {
    ++frames_since_detection_;
    Eigen::Matrix2Xd predicted = *last_landmarks_;
    if (landmark_velocity_px_) predicted.colwise() += *landmark_velocity_px_;
    return Candidate{box_from_landmarks(predicted), false};
  }
  std::vector<FaceBox> boxes;
  const std::optional<cv::Rect2d> hint = std::exchange(search_hint_, std::nullopt);
  if (last_box_) boxes = detector_.detect_around(gray, *last_box_);
  else if (hint) boxes = detector_.detect_around(gray, *hint);
  if (boxes.empty() && landmark_box_ready) {
    // The detector misses turned faces the landmarks still follow: keep tracking from the landmarks
    // for a while, but a face the detector keeps missing is lost (the landmark detector always
    // returns a face-like shape, even on a wall).
    result.faces_found = 0;
    if (++detector_misses_ > config_.limits.max_detector_misses) {
      detector_misses_ = 0;
      result.reason = FaceLostReason::NotConfirmed;
      return std::nullopt;
    }
    frames_since_detection_ = 0;
    return Candidate{box_from_landmarks(*last_landmarks_), false};
  }
  if (!boxes.empty()) detector_misses_ = 0;
  if (boxes.empty() && !hint) {
    const auto& scales = config_.lost_search_scales;
    boxes = detector_.detect_full(gray, scales[lost_search_cycle_++ % scales.size()]);
  }
  result.faces_found = static_cast<int>(boxes.size());
  if (boxes.empty()) {
    result.reason = FaceLostReason::NoFace;
    return std::nullopt;
  }
  frames_since_detection_ = 0;
  return select_among(gray, boxes, result);
}

FaceResult FacePoseEstimator::lose(FaceResult result, FaceLostReason reason) {
  result.state = FaceState::Lost;
  result.reason = reason;
  result.T_cam_face = Eigen::Isometry3d::Identity();
  result.quality = 0;
  last_landmarks_.reset();
  landmark_velocity_px_.reset();
  last_pose_.reset();
  solver_.reset();
  // Keep searching around the last box for a few frames before going back to full-frame searches.
  if (++lost_frames_ > 5) last_box_.reset();
  return result;
}

void FacePoseEstimator::set_landmark_weights(PnpProblem& problem) const {
  const bool far_side = config_.far_side_yaw_rad > 0 && last_pose_.has_value();
  if (!config_.landmark_noise_weights && !far_side) {
    problem.weights = view_weights_;  // a start's mirrored far side, else empty
    return;
  }
  if (config_.landmark_noise_weights) {
    problem.weights = noise_weights_;
  } else {
    problem.weights.setOnes(problem.points_face.cols());
  }
  if (far_side) {
    apply_far_side_weights(problem.points_face, head_angles(last_pose_->linear()).yaw, config_.far_side_yaw_rad,
                           problem.weights);
  }
  if (view_weights_.size() == problem.weights.size()) problem.weights.array() *= view_weights_.array();
}

std::optional<PnpSolution> FacePoseEstimator::fit_pose(const Eigen::Matrix2Xd& lm, const Eigen::VectorXd& weights) const {
  const PnpProblem problem{points_face_, ideal_pixels(lm), ideal_camera(), weights};
  const auto init = solve_epnp(problem);
  return init ? refine_lm(problem, init->T_cam_face, config_.solver.lm) : std::nullopt;
}

void FacePoseEstimator::detect_landmarks(const cv::Mat& gray, const Candidate& candidate, Eigen::Matrix2Xd& lm) {
  view_weights_.resize(0);
  if (last_pose_ &&
      detect_in_frontal_view(gray, candidate, *last_pose_, landmark_velocity_px_.value_or(Eigen::Vector2d::Zero()), lm)) {
    return;
  }
  const double upright = config_.upright_crop && last_landmarks_ ? eye_line_angle(*last_landmarks_) : 0.0;
  double widen = 1;
  if (config_.yaw_widen_exponent > 0 && last_pose_) {
    const double yaw = head_angles(last_pose_->linear()).yaw;
    widen = std::min(1.6, std::pow(1.0 / std::max(std::cos(yaw), 0.1), config_.yaw_widen_exponent));
  }
  landmark_detector_.detect(gray, candidate.box, lm, upright, widen);
  // The first frame of a track has no pose to make the frontal view from, so the crop's landmarks
  // carry the predictor's pull towards a frontal shape (a turned head seen less turned and farther),
  // and under the relative-motion protocol that first pose's error is carried through the whole
  // track. Pose them once (the solver's state untouched) and run the predictor again on the frontal
  // view at that pose: the first frame then gets the landmarks every later frame gets.
  if (frontal_ && !last_pose_) {
    const auto provisional = fit_pose(lm);
    if (provisional && plausible_distance(*provisional)) {
      // The view's box comes from the detector's box relation, which a new track has not measured
      // yet (it is set at the end of a tracked frame): measure it now, on this detector box.
      // Kept for the rest of the frame: measured on the crop's landmarks, whose spread is the one the
      // frontal view's box is placed by (the view's landmarks of a turned head, mapped back to the
      // image, are not).
      if (candidate.from_detector) {
        remember_box_relation(candidate.box, lm, provisional->T_cam_face.translation().z());
        box_relation_measured_ = true;
      }
      if (!detect_in_frontal_view(gray, candidate, provisional->T_cam_face, Eigen::Vector2d::Zero(), lm, true)) return;
      // The view made at a pose off by δ still shows the face turned by δ, and the predictor follows
      // that only in part, so one view leaves part of the crop's error (at 44° of yaw, 1.3 m: +100 mm
      // in distance after one view, +13 mm after five more with the far side mirrored). Iterate: each
      // view at the last pass's pose, until the pose stops moving.
      Eigen::Isometry3d pose = provisional->T_cam_face;
      for (int pass = 1; pass < config_.start_view_passes; ++pass) {
        const auto refit = fit_pose(lm, view_weights_);
        if (!refit || !plausible_distance(*refit)) break;
        const double moved_m = (refit->T_cam_face.translation() - pose.translation()).norm();
        const double turned = Eigen::AngleAxisd(refit->T_cam_face.linear() * pose.linear().transpose()).angle();
        pose = refit->T_cam_face;
        if (moved_m < kStartPassMovedM && turned < kStartPassTurnedRad) break;
        if (!detect_in_frontal_view(gray, candidate, pose, Eigen::Vector2d::Zero(), start_lm_, true)) break;
        lm = start_lm_;
      }
    }
  }
}

bool FacePoseEstimator::plausible_distance(const PnpSolution& s) const {
  const double distance = s.T_cam_face.translation().norm();
  return distance >= config_.limits.min_distance_m && distance <= config_.limits.max_distance_m;
}

bool FacePoseEstimator::detect_in_frontal_view(const cv::Mat& gray, const Candidate& candidate,
                                               const Eigen::Isometry3d& T_cam_face, const Eigen::Vector2d& shift,
                                               Eigen::Matrix2Xd& lm, bool start) {
  if (!frontal_) return false;
  const double fx = camera_.intrinsics().fx;
  const double distance = T_cam_face.translation().norm();
  const double side_px = box_side_m_ * fx / distance;
  // Only for the face being tracked: a detector box elsewhere (another face) takes the plain crop.
  const auto origin = camera_.project(T_cam_face.translation());
  if (!origin) return false;
  const Eigen::Vector2d o = *origin + shift;
  const cv::Point2d bc = centre(candidate.box);
  if (std::hypot(bc.x - o.x(), bc.y - o.y()) > 0.5 * side_px) return false;
  // The same working resolution as the plain crop: the box about 160 px wide, a margin of 0.3 box.
  const double scale = std::max(1.0, 160.0 / side_px);
  const double side = side_px * scale;
  const int size = static_cast<int>(std::ceil(1.6 * side));
  if (!frontal_->render(gray, camera_, T_cam_face, shift, fx * scale, cv::Size(size, size))) return false;
  Eigen::Vector2d c = Eigen::Vector2d::Zero();
  for (Eigen::Index i = 0; i < points_face_.cols(); ++i) c += frontal_->view_of(points_face_.col(i));
  c = c / static_cast<double>(points_face_.cols()) + box_offset_ * side;
  view_weights_.resize(0);
  const double yaw = head_angles(T_cam_face.linear()).yaw;
  const double mirror = start && config_.start_mirror_yaw_rad > 0
                            ? std::clamp((std::abs(yaw) - config_.start_mirror_yaw_rad) / kMirrorRampRad, 0.0, 1.0)
                            : 0.0;
  const cv::Mat& view = mirror > 0 ? mirror_far_side(yaw, mirror, fx * scale / distance) : frontal_->image();
  landmark_detector_.detect_in(view, cv::Rect2d(c.x() - side / 2, c.y() - side / 2, side, side), view_landmarks_);
  lm.resize(2, 68);
  for (Eigen::Index i = 0; i < 68; ++i) lm.col(i) = frontal_->image_of(view_landmarks_.col(i));
  return true;
}

const cv::Mat& FacePoseEstimator::mirror_far_side(double yaw, double mirror, double view_px_per_m) {
  // The view is the face seen head-on with its midline (face x = 0) on the view's centre column, so
  // the near side's mirror image is the view flipped about that column. The far side is x > 0 (the
  // subject's left) when the yaw is negative.
  const double far_sign = yaw < 0 ? 1.0 : -1.0;
  const double mid = (frontal_->image().cols - 1) / 2.0;
  // How much of the mirror image a view column (or a landmark) takes: none up to kMirrorStartM from
  // the midline, so that the nose (the yaw cue) stays the image's own; fully kMirrorWidthM farther.
  const auto amount = [&](double x_px) {
    return mirror * std::clamp((far_sign * (x_px - mid) / view_px_per_m - kMirrorStartM) / kMirrorWidthM, 0.0, 1.0);
  };
  cv::flip(frontal_->image(), flipped_, 1);
  frontal_->image().copyTo(mirrored_);
  for (int x = 0; x < mirrored_.cols; ++x) {
    const double a = amount(x);
    if (a <= 0) continue;
    for (int y = 0; y < mirrored_.rows; ++y) {
      auto& out = mirrored_.at<unsigned char>(y, x);
      out = static_cast<unsigned char>(std::lround((1 - a) * out + a * flipped_.at<unsigned char>(y, x)));
    }
  }
  // A landmark found on the mirror image carries no evidence of where the far side is.
  view_weights_.resize(points_face_.cols());
  for (Eigen::Index i = 0; i < points_face_.cols(); ++i) {
    view_weights_(i) = 1.0 - amount(frontal_->view_of(points_face_.col(i)).x());
  }
  return mirrored_;
}

FaceLostReason FacePoseEstimator::pose_landmarks(const cv::Mat& gray, const Candidate& candidate, FaceResult& result,
                                                 Eigen::Matrix2Xd& lm, std::optional<FacePoseEstimate>& estimate) {
  double start = process_cpu_seconds();
  detect_landmarks(gray, candidate, lm);
  result.timings.landmarks_ms += ms_since(start);
  result.landmarks = lm;
  result.box = candidate.box;

  const auto& L = config_.limits;
  for (int id : model_.landmark_ids()) {
    if (!camera_.in_image(lm.col(id), L.border_margin_px)) return FaceLostReason::CutByBorder;
  }
  const double iod = interocular_px(lm);
  if (iod < L.min_interocular_px) return FaceLostReason::TooSmall;

  start = process_cpu_seconds();
  problem_.points_face = points_face_;
  problem_.pixels = ideal_pixels(lm);
  set_landmark_weights(problem_);
  result.landmark_weights = problem_.weights;
  estimate = solver_.solve(problem_, std::max(iod / 60.0, 0.5));
  result.timings.pose_ms += ms_since(start);
  if (!estimate) return FaceLostReason::NoPose;
  result.reprojection_rms_px = reprojection_rms(problem_, estimate->solution.T_cam_face);
  if (result.reprojection_rms_px / iod > L.max_rms_per_interocular) return FaceLostReason::InconsistentLandmarks;
  return FaceLostReason::None;
}

FaceResult FacePoseEstimator::process(const cv::Mat& gray, Seconds t) {
  FaceResult result;
  result.t = t;
  if (gray.empty() || gray.type() != CV_8UC1 || gray.cols != camera_.width() || gray.rows != camera_.height()) {
    return lose(result, FaceLostReason::BadImage);
  }
  double start = process_cpu_seconds();
  auto candidate = choose_box(gray, result);
  // Everything after takes the box as the predictor's: the crop, the view's box relation.
  if (candidate && candidate->from_detector) candidate->box = settled_box(gray, candidate->box);
  result.timings.detect_ms = ms_since(start);
  if (!candidate) return lose(result, result.reason);

  box_relation_measured_ = false;
  Eigen::Matrix2Xd lm;
  std::optional<FacePoseEstimate> estimate;
  FaceLostReason why = pose_landmarks(gray, *candidate, result, lm, estimate);
  // A tracked frame's landmarks come from one frontal view made at the last pose, unmirrored; on a
  // head turned 35-50° its far side is too foreshortened for them to fit, where a track's first frame
  // (iterated views, the far side mirrored) still fits: in flight such faces were lost on every other
  // frame, found again as a new track on the next. With restart_unfit_tracked_frames the frame is made
  // again as a first frame (the motion checks below still hold it to the last pose).
  if (why == FaceLostReason::InconsistentLandmarks && last_pose_ && frontal_ && config_.restart_unfit_tracked_frames) {
    const std::optional<Eigen::Isometry3d> tracked = std::exchange(last_pose_, std::nullopt);
    why = pose_landmarks(gray, *candidate, result, lm, estimate);
    last_pose_ = tracked;
    result.restarted = true;
  }
  if (why != FaceLostReason::None) return lose(result, why);

  const auto& L = config_.limits;
  const PnpSolution& s = estimate->solution;
  const double iod = interocular_px(lm);
  const double rms_ratio = result.reprojection_rms_px / iod;
  result.angles = head_angles(s.T_cam_face.linear());
  if (std::abs(result.angles.yaw) > L.max_yaw_rad || std::abs(result.angles.pitch) > L.max_pitch_rad) {
    return lose(result, FaceLostReason::BeyondProfile);
  }
  if (!plausible_distance(s)) return lose(result, FaceLostReason::ImplausibleDistance);
  // A track's first pose has no earlier pose to make the frontal view from, and at a large yaw the
  // view made at its own provisional pose still carries the predictor's pull towards a frontal face
  // (it reads the face less turned and 50-100 mm farther at 44° and 1.3 m, docs/face.md). Every later
  // frame's view starts from it and the error decays only as the head turns back, so wait for a less
  // turned face to start from.
  if (!last_pose_ && std::abs(result.angles.yaw) > L.max_start_yaw_rad) {
    return lose(result, FaceLostReason::TurnedAtStart);
  }

  const double spread = centroid_and_spread(lm).second;
  if (last_pose_ && last_landmarks_) {
    const double jump = (s.T_cam_face.translation() - last_pose_->translation()).norm();
    const double turn = Eigen::AngleAxisd(s.T_cam_face.linear() * last_pose_->linear().transpose()).angle();
    const double scale = std::abs(spread / last_spread_px_ - 1.0);
    if (jump > L.max_jump_m || turn > L.max_turn_rad || scale > L.max_scale_change) {
      return lose(result, FaceLostReason::ImplausibleMotion);
    }
  }

  result.state = FaceState::Tracking;
  result.reason = FaceLostReason::None;
  result.T_cam_face = s.T_cam_face;
  result.line_of_sight_cam = line_of_sight(s.T_cam_face.linear());
  result.quality = std::clamp(1.0 - rms_ratio / L.max_rms_per_interocular, 0.0, 1.0);
  result.reinitialised = estimate->reinitialised;

  if (candidate->from_detector && !box_relation_measured_) remember_box_relation(candidate->box, lm, s.T_cam_face.translation().z());
  if (last_landmarks_) {
    landmark_velocity_px_ = (lm.middleCols(17, 43) - last_landmarks_->middleCols(17, 43)).rowwise().mean();
  }
  last_landmarks_ = lm;
  last_pose_ = s.T_cam_face;
  last_spread_px_ = spread;
  last_box_ = candidate->box;
  lost_frames_ = 0;
  return result;
}

}  // namespace labo::face
