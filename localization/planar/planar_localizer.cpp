#include "localization/planar/planar_localizer.hpp"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <array>
#include <cmath>
#include <string_view>
#include <vector>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

namespace labo::planar {

namespace {

// How long the last pose's distance still chooses the detector, and still serves for continuity.
constexpr Seconds kRecentPoseS = 2.0;
// Two poses closer than this are one (the IPPE pair, refined poses).
constexpr double kDistinctPosesRad = 2.0 * 3.14159265358979 / 180.0;
// Two refined IPPE branches whose photometric residuals are within this ratio are not told apart
// reliably: at 4-6 m the two lie 10-25 deg apart with residuals 1-5 % apart, and the lower residual
// may pick the wrong one while the refinement's own sigma claims a few degrees. The pose is then the
// midway between the two (below), and its rotation sigma covers both branches. Test "planar: two
// refined IPPE branches the fit cannot tell apart give the pose midway between them".
constexpr double kUnresolvedResidualRatio = 1.15;
// Template-matching scale window around a predicted width.
constexpr double kPredictedWidthFactor = 1.6;
// Motion blur: modelled when the panel moved at least this far since a frame at most this old, with
// the exposure tried at these fractions of the frame interval (0 is always tried first).
constexpr double kMinBlurMotionPx = 2.0;
constexpr Seconds kMaxBlurIntervalS = 0.1;
constexpr std::array<double, 4> kExposureFractions{1.0 / 3.0, 2.0 / 3.0, 1.0, 4.0 / 3.0};

Se3RefinerSettings se3_settings(const PlanarConfig& config, double min_correlation, const PinholeCamera& camera) {
  Se3RefinerSettings s = config.se3;
  s.min_correlation = min_correlation;
  s.calibration_error_px = camera.intrinsics().calibration_error_px;
  return s;
}

// The pose midway between two refined poses (rotation by slerp, translation averaged); the other
// fields are the lower residual's.
Se3Refinement midway(const Se3Refinement& a, const Se3Refinement& b) {
  Se3Refinement m = a.residual_grey <= b.residual_grey ? a : b;
  const Eigen::Quaterniond qa(a.T_cam_object.linear()), qb(b.T_cam_object.linear());
  m.T_cam_object.linear() = qa.slerp(0.5, qb).normalized().toRotationMatrix();
  m.T_cam_object.translation() = 0.5 * (a.T_cam_object.translation() + b.T_cam_object.translation());
  return m;
}

// The panel's other pose of (nearly) the same image: its normal reflected about the line of sight to
// its centre, the centre kept (the relation between IPPE's two solutions).
Eigen::Isometry3d mirrored_about_line_of_sight(const Eigen::Isometry3d& T) {
  const Eigen::Vector3d v = T.translation().normalized();
  const Eigen::Vector3d n = T.linear().col(2);
  const Eigen::Vector3d n_mirror = 2 * n.dot(v) * v - n;
  Eigen::Isometry3d out = T;
  out.linear() = Eigen::Quaterniond::FromTwoVectors(n, n_mirror).toRotationMatrix() * T.linear();
  return out;
}

// A polygon of at most 8 vertices: a quadrilateral clipped by a rectangle (each of its 4 edges adds
// at most one vertex). Fixed storage: the per-frame checks allocate nothing.
struct SmallPolygon {
  std::array<cv::Point2d, 8> v;
  std::size_t n = 0;
};

// Shoelace area, positive whatever the orientation.
double polygon_area(const SmallPolygon& p) {
  double twice = 0;
  for (std::size_t i = 0, j = p.n - 1; i < p.n; j = i++) twice += p.v[j].x * p.v[i].y - p.v[i].x * p.v[j].y;
  return 0.5 * std::abs(twice);
}

// Sutherland-Hodgman: the part of `in` on the side of the line where inside(point) holds; `cross`
// gives the edge's intersection with the line. Right for any simple polygon against a convex window.
template <typename Inside, typename Cross>
SmallPolygon clip(const SmallPolygon& in, Inside inside, Cross cross) {
  SmallPolygon out;
  if (in.n == 0) return out;
  for (std::size_t i = 0, j = in.n - 1; i < in.n; j = i++) {
    const cv::Point2d& a = in.v[j];
    const cv::Point2d& b = in.v[i];
    const bool a_in = inside(a), b_in = inside(b);
    if (a_in != b_in && out.n < out.v.size()) out.v[out.n++] = cross(a, b);
    if (b_in && out.n < out.v.size()) out.v[out.n++] = b;
  }
  return out;
}

// How much of the quad is in view: the fraction of its area inside the image, and the fraction of the
// image it covers (pixel centres at integers, so the image spans -0.5 .. size - 0.5).
struct InView {
  double of_panel = 0, of_image = 0;
  SmallPolygon inside;  // the quad clipped by the image
};

InView in_view(const std::array<cv::Point2d, 4>& corners, cv::Size size) {
  SmallPolygon quad;
  for (const auto& c : corners) quad.v[quad.n++] = c;
  const double area = polygon_area(quad);
  if (!(area > 1.0)) return {};
  const double x0 = -0.5, y0 = -0.5, x1 = size.width - 0.5, y1 = size.height - 0.5;
  const auto at_x = [](double x) {
    return [x](const cv::Point2d& a, const cv::Point2d& b) { return cv::Point2d(x, a.y + (b.y - a.y) * (x - a.x) / (b.x - a.x)); };
  };
  const auto at_y = [](double y) {
    return [y](const cv::Point2d& a, const cv::Point2d& b) { return cv::Point2d(a.x + (b.x - a.x) * (y - a.y) / (b.y - a.y), y); };
  };
  SmallPolygon p = clip(quad, [&](const cv::Point2d& q) { return q.x >= x0; }, at_x(x0));
  p = clip(p, [&](const cv::Point2d& q) { return q.x <= x1; }, at_x(x1));
  p = clip(p, [&](const cv::Point2d& q) { return q.y >= y0; }, at_y(y0));
  p = clip(p, [&](const cv::Point2d& q) { return q.y <= y1; }, at_y(y1));
  if (p.n < 3) return {};
  const double inside = polygon_area(p);
  return {std::clamp(inside / area, 0.0, 1.0), std::clamp(inside / (static_cast<double>(size.width) * size.height), 0.0, 1.0), p};
}

// Four well spread points of the panel in view, for a panel larger than the view (its corners far
// outside the image): the vertices of the part in view nearest the corners of its bounding box,
// moved 5 % towards its centre. False when they are not four distinct vertices.
bool points_in_view(const SmallPolygon& inside, std::array<cv::Point2d, 4>& points) {
  if (inside.n < 4) return false;
  cv::Point2d lo = inside.v[0], hi = inside.v[0], centre(0, 0);
  for (std::size_t i = 0; i < inside.n; ++i) {
    lo = {std::min(lo.x, inside.v[i].x), std::min(lo.y, inside.v[i].y)};
    hi = {std::max(hi.x, inside.v[i].x), std::max(hi.y, inside.v[i].y)};
    centre += inside.v[i] * (1.0 / static_cast<double>(inside.n));
  }
  const std::array<cv::Point2d, 4> box{lo, cv::Point2d(hi.x, lo.y), hi, cv::Point2d(lo.x, hi.y)};
  std::array<std::size_t, 4> chosen{};
  for (std::size_t k = 0; k < 4; ++k) {
    for (std::size_t i = 1; i < inside.n; ++i) {
      if (cv::norm(inside.v[i] - box[k]) < cv::norm(inside.v[chosen[k]] - box[k])) chosen[k] = i;
    }
    for (std::size_t j = 0; j < k; ++j) {
      if (chosen[j] == chosen[k]) return false;
    }
    points[k] = inside.v[chosen[k]] + 0.05 * (centre - inside.v[chosen[k]]);
  }
  return true;
}

}  // namespace

const char* to_string(PlanarState s) {
  switch (s) {
    case PlanarState::Searching: return "searching";
    case PlanarState::Detected: return "detected";
    case PlanarState::Tracking: return "tracking";
    case PlanarState::Lost: return "lost";
  }
  return "?";
}

const char* to_string(PlanarMethod m) {
  switch (m) {
    case PlanarMethod::None: return "none";
    case PlanarMethod::TemplateMatching: return "template";
    case PlanarMethod::Features: return "features";
    case PlanarMethod::Ecc: return "ecc";
    case PlanarMethod::InverseCompositional: return "ic";
  }
  return "?";
}

const char* to_string(PlanarLoss l) {
  switch (l) {
    case PlanarLoss::None: return "none";
    case PlanarLoss::NotFound: return "not_found";
    case PlanarLoss::NoConvergence: return "no_convergence";
    case PlanarLoss::LowCorrelation: return "low_correlation";
    case PlanarLoss::OutOfView: return "out_of_view";
    case PlanarLoss::PoseJump: return "pose_jump";
    case PlanarLoss::TurnJump: return "turn_jump";
    case PlanarLoss::NoPose: return "no_pose";
    case PlanarLoss::BadFrame: return "bad_frame";
  }
  return "?";
}

PlanarObjectThresholds PlanarObjectThresholds::from(const VisionThresholds& vision, std::optional<double> lambda_m,
                                                    std::optional<int> min_inliers) {
  PlanarObjectThresholds t;
  t.min_correlation = vision.template_correlation_alpha;
  t.max_jump_m = vision.distance_jump_m;
  t.max_turn_rad = vision.angle_jump_beta_rad;
  t.sift_switch_distance_m = lambda_m.value_or(vision.sift_switch_distance_m);
  t.sift_min_inliers = min_inliers.value_or(vision.sift_min_inliers);
  return t;
}

PlanarObjectLocalizer::PlanarObjectLocalizer(PlanarTemplate planar_template, const PinholeCamera& camera,
                                             const PlanarObjectThresholds& thresholds, const PlanarConfig& config)
    : template_(std::move(planar_template)),
      camera_(camera),
      thresholds_(thresholds),
      config_(config),
      tracker_(make_homography_tracker(config.tracker, template_.working(), config)),
      template_detector_(template_.working(), cv::Size(camera.width(), camera.height()), config, thresholds.min_correlation),
      feature_detector_(template_.working(), cv::Size(camera.width(), camera.height()), config, thresholds.sift_min_inliers),
      pose_solver_(camera.K(), template_.object_corners()),
      pose_refiner_(template_.working(), template_.width_m(), template_.height_m(), camera.K(),
                    se3_settings(config, thresholds.min_correlation, camera)) {
  if (config.pose_refinement == PoseRefinement::Se3 && config.se3_footprint_model) {
    footprint_refiner_.emplace(template_.original(), template_.width_m(), template_.height_m(), camera, se3_settings(config, thresholds.min_correlation, camera));
  }
  if (camera_.has_distortion()) {
    const cv::Size size(camera_.width(), camera_.height());
    cv::Mat map_x, map_y;
    cv::initUndistortRectifyMap(camera_.K(), camera_.distortion_coefficients(), cv::Mat(), camera_.K(), size,
                                CV_32FC1, map_x, map_y);
    undistortion_ = LinearRemap8u(map_x, map_y, size);
    undistorted_.create(size, CV_8UC1);
  }
}

void PlanarObjectLocalizer::reset() {
  tracking_ = false;
  last_pose_.reset();
  unverified_pose_.reset();
  last_exposure_ = -1;
}

const cv::Mat& PlanarObjectLocalizer::undistort(const cv::Mat& gray) {
  if (undistortion_.empty()) return gray;
  undistortion_.apply(gray, undistorted_);  // cv::remap's pixels, without its per-call allocations
  return undistorted_;
}

PlanarResult PlanarObjectLocalizer::process(const cv::Mat& gray, Seconds t, std::optional<double> predicted_distance_m) {
  PlanarResult r;
  r.t = t;
  r.state = tracking_ ? PlanarState::Lost : (ever_found_ ? PlanarState::Lost : PlanarState::Searching);
  if (gray.empty() || gray.type() != CV_8UC1 || gray.cols != camera_.width() || gray.rows != camera_.height()) {
    r.reason = PlanarLoss::BadFrame;
    r.detail = gray.empty()                ? "empty frame"
               : gray.type() != CV_8UC1    ? "frame is not 8-bit single-channel grey"
                                           : "frame size differs from the camera's";
    return r;
  }
  raw_ = gray;
  const cv::Mat& image = undistort(gray);
  if (tracking_) return track(image, r);
  std::optional<double> distance = predicted_distance_m;
  if (!distance && last_pose_ && t - last_pose_t_ < kRecentPoseS) distance = last_pose_->translation().norm();
  return detect(image, r, distance);
}

PlanarResult PlanarObjectLocalizer::track(const cv::Mat& image, PlanarResult r) {
  r.method = tracker_->kind() == TrackerKind::Ecc ? PlanarMethod::Ecc : PlanarMethod::InverseCompositional;
  const HomographyTrackOutcome o = tracker_->track(image, H_working_);
  r.correlation = o.correlation;
  PlanarLoss loss = PlanarLoss::NoConvergence;
  if (!o.converged) {
    r.detail = o.failure;
    if (std::string_view(o.failure) == "object out of view") loss = PlanarLoss::OutOfView;
  } else {
    loss = accept(image, o.H, o.correlation, true, r);
  }
  if (loss == PlanarLoss::None) {
    r.state = PlanarState::Tracking;
    detection_confirmed_ = true;
    return r;
  }
  // A detection that the very next frame could not follow may have been a look-alike: its distance
  // must not narrow the searches that follow (tests/localization/planar/planar_localizer_test.cpp,
  // "a detection lost at once does not steer the next searches").
  if (!detection_confirmed_) last_pose_.reset();
  tracking_ = false;
  r.state = PlanarState::Lost;
  r.reason = loss;
  r.has_pose = false;
  return r;
}

PlanarResult PlanarObjectLocalizer::detect(const cv::Mat& image, PlanarResult r, std::optional<double> distance_m) {
  std::array<PlanarMethod, 2> order{PlanarMethod::TemplateMatching, PlanarMethod::Features};
  int count = 2;
  if (distance_m) {
    order[0] = *distance_m < thresholds_.sift_switch_distance_m ? PlanarMethod::Features : PlanarMethod::TemplateMatching;
    count = 1;
  }
  r.reason = PlanarLoss::NotFound;
  for (int i = 0; i < count; ++i) {
    Detection d;
    if (order[static_cast<std::size_t>(i)] == PlanarMethod::Features) {
      d = feature_detector_.detect(image);
      r.inliers = d.inliers;
    } else {
      double lo = config_.detection_min_width_fraction * image.cols;
      double hi = config_.detection_max_width_fraction * image.cols;
      if (distance_m && *distance_m > 0) {
        const double expected = camera_.intrinsics().fx * template_.width_m() / *distance_m;
        lo = std::max(lo, expected / kPredictedWidthFactor);
        hi = std::min(hi, expected * kPredictedWidthFactor);
      }
      if (lo <= hi) d = template_detector_.detect(image, lo, hi);
    }
    if (!d.found) continue;
    r.method = order[static_cast<std::size_t>(i)];
    // The detector's homography is coarse: the tracker refines it, and the same checks as in
    // tracking (without the jump test: the drone may have moved anywhere while lost) decide.
    const HomographyTrackOutcome o = tracker_->track(image, d.H);
    r.correlation = o.correlation;
    if (!o.converged) {
      r.reason = PlanarLoss::NoConvergence;
      r.detail = o.failure;
      continue;
    }
    r.reason = accept(image, o.H, o.correlation, false, r);
    if (r.reason == PlanarLoss::None) {
      r.state = PlanarState::Detected;
      tracking_ = true;
      detection_confirmed_ = false;
      ever_found_ = true;
      return r;
    }
  }
  r.has_pose = false;
  r.state = ever_found_ ? PlanarState::Lost : PlanarState::Searching;
  return r;
}

PlanarLoss PlanarObjectLocalizer::accept(const cv::Mat& image, const cv::Matx33d& H_working, double correlation,
                                         bool check_jump, PlanarResult& r) {
  if (correlation < thresholds_.min_correlation) return PlanarLoss::LowCorrelation;
  const auto corners = map_corners(H_working, template_.working_corners());
  const InView view = in_view(corners, cv::Size(camera_.width(), camera_.height()));
  r.visible_fraction = view.of_panel;
  r.image_fraction = view.of_image;
  // Enough of the panel to fit: most of it, or (an object larger than the view: the platform below
  // ~0.7 m) a part that fills the image.
  if (r.visible_fraction < config_.min_visible_fraction && r.image_fraction < config_.min_image_fraction) {
    r.detail = "too little of the panel inside the image";
    return PlanarLoss::OutOfView;
  }
  const std::optional<Eigen::Isometry3d> previous =
      last_pose_ && r.t - last_pose_t_ < kRecentPoseS ? last_pose_ : std::nullopt;
  // A panel larger than the view (in view by the image rule) is solved from points in view.
  const bool larger_than_view = r.visible_fraction < config_.min_visible_fraction;
  std::array<cv::Point2d, 4> points;
  std::optional<PlanarPose> pose = larger_than_view && points_in_view(view.inside, points)
                                       ? pose_solver_.solve(object_points(H_working, points), points, previous)
                                       : pose_solver_.solve(corners, previous);
  if (!pose) return PlanarLoss::NoPose;
  SmallPolygon quad;
  for (const auto& c : corners) quad.v[quad.n++] = c;
  // The panel's size in the image, for the uncertainty of a pose from its corners: of the part in view.
  const double size_px = std::sqrt(polygon_area(larger_than_view ? view.inside : quad));
  const double margin = std::clamp((correlation - thresholds_.min_correlation) / (1.0 - thresholds_.min_correlation), 0.0, 1.0);
  if (!refine_pose(image, *pose, size_px, margin, r)) {
    unverified_pose_ = pose->T_cam_object;
    unverified_pose_t_ = r.t;
    // On the bench's sequences every such pose is 4-10 deg off (a panel partly out of view, a
    // detection on a smeared frame; docs/planar.md): the tracker's homography has gone wrong.
    r.detail = "the photometric fit contradicts the tracker's homography";
    return PlanarLoss::NoPose;
  }
  if (check_jump && last_pose_) {
    // Motion between consecutive frames, measured as the object's displacement in the camera frame.
    // (The camera's position in the object frame, -R^T t, would carry the plane's tilt uncertainty
    // times the range: a few degrees at 3 m already make 0.3 m, and the test would fire on noise.)
    const double moved = (pose->T_cam_object.translation() - last_pose_->translation()).norm();
    if (moved > thresholds_.max_jump_m) return PlanarLoss::PoseJump;
    if (rotation_angle(last_pose_->linear(), pose->T_cam_object.linear()) > thresholds_.max_turn_rad) {
      return PlanarLoss::TurnJump;
    }
  }
  H_working_ = H_working;
  last_pose_ = pose->T_cam_object;
  last_pose_t_ = r.t;

  r.has_pose = true;
  r.H = H_working * template_.working_from_original();
  for (std::size_t i = 0; i < 4; ++i) {
    // Back through the lens: undistorted pixel -> normalized -> distorted pixel.
    const auto& k = camera_.intrinsics();
    const Eigen::Vector3d ray((corners[i].x - k.cx) / k.fx, (corners[i].y - k.cy) / k.fy, 1.0);
    const auto raw = camera_.project(ray);
    r.image_corners[i] = raw ? cv::Point2d(raw->x(), raw->y()) : corners[i];
  }
  r.T_cam_object = pose->T_cam_object;
  r.distance_m = pose->T_cam_object.translation().norm();
  r.reprojection_error_px = pose->reprojection_error_px;
  r.pose_ambiguous = pose->ambiguous;
  const double seen = std::max(r.visible_fraction, r.image_fraction);
  r.quality = margin * seen * (pose->ambiguous ? 0.5 : 1.0) / (1.0 + pose->reprojection_error_px);
  return PlanarLoss::None;
}

std::array<Eigen::Vector2d, 4> PlanarObjectLocalizer::object_points(const cv::Matx33d& H_working,
                                                                   const std::array<cv::Point2d, 4>& image_points) const {
  const cv::Matx33d to_template = H_working.inv();
  const cv::Size w = template_.working().size();
  std::array<Eigen::Vector2d, 4> out;
  for (std::size_t k = 0; k < 4; ++k) {
    const cv::Point2d u = apply_homography(to_template, image_points[k]);
    out[k] = Eigen::Vector2d(((u.x + 0.5) / w.width - 0.5) * template_.width_m(), ((u.y + 0.5) / w.height - 0.5) * template_.height_m());
  }
  return out;
}

Eigen::Vector2d PlanarObjectLocalizer::panel_motion_px(const Eigen::Isometry3d& T, Seconds t) const {
  const auto centre_px = [&](const Eigen::Isometry3d& pose) {
    const Eigen::Vector3d c = pose.translation();
    return Eigen::Vector2d(camera_.intrinsics().fx * c.x() / c.z(), camera_.intrinsics().fy * c.y() / c.z());
  };
  // The most recent reference: the last reported pose, or a later unverified one.
  const bool unverified = unverified_pose_ && (!last_pose_ || unverified_pose_t_ > last_pose_t_);
  const std::optional<Eigen::Isometry3d>& reference = unverified ? unverified_pose_ : last_pose_;
  const Seconds reference_t = unverified ? unverified_pose_t_ : last_pose_t_;
  const bool recent = reference && t - reference_t > 0 && t - reference_t <= kMaxBlurIntervalS;
  return recent ? Eigen::Vector2d(centre_px(T) - centre_px(*reference)) : Eigen::Vector2d::Zero();
}

Se3Refinement PlanarObjectLocalizer::refine_once(const Eigen::Isometry3d& T_start, bool use_footprint,
                                                 const Eigen::Vector2d& blur_px, const Eigen::Isometry3d* warm_start) const {
  if (use_footprint && footprint_refiner_) return footprint_refiner_->refine(T_start, warm_start);
  return pose_refiner_.refine(smoothed_, T_start, blur_px, warm_start);
}

Se3Refinement PlanarObjectLocalizer::refine_with_blur_search(const Eigen::Isometry3d& T_start, Seconds t, bool use_footprint,
                                                             Eigen::Vector2d& blur_px, int& iterations) {
  blur_px.setZero();
  // The panel's image motion since the previous frame; the exposure is an unknown part of the frame
  // interval (auto exposure), so a few fractions of that motion are tried and the best fit kept.
  const Eigen::Vector2d motion_px = panel_motion_px(T_start, t);
  if (!(motion_px.norm() >= kMinBlurMotionPx)) {
    last_exposure_ = -1;
    Se3Refinement only = refine_once(T_start, use_footprint);
    iterations += only.iterations;
    return only;
  }
  // Hypotheses -1 (no blur) .. 3 (kExposureFractions); the residual is unimodal in the exposure. The
  // search starts at the last frame's choice and walks towards lower residuals, each refinement
  // starting from the best pose so far.
  constexpr int kCount = static_cast<int>(kExposureFractions.size());
  std::array<std::optional<Se3Refinement>, kExposureFractions.size() + 1> tried;
  int best_index = -2;
  enum class Fit { Better, Worse, Failed };
  const auto evaluate = [&](int k) {
    if (k < -1 || k >= kCount || tried[static_cast<std::size_t>(k + 1)]) return Fit::Worse;
    const Eigen::Isometry3d* warm = best_index >= -1 ? &tried[static_cast<std::size_t>(best_index + 1)]->T_cam_object : nullptr;
    const Eigen::Vector2d blur = k < 0 ? Eigen::Vector2d::Zero() : Eigen::Vector2d(kExposureFractions[static_cast<std::size_t>(k)] * motion_px);
    tried[static_cast<std::size_t>(k + 1)] = pose_refiner_.refine(smoothed_, T_start, blur, warm);
    const Se3Refinement& c = *tried[static_cast<std::size_t>(k + 1)];
    iterations += c.iterations;
    if (!c.refined) return Fit::Failed;  // e.g. beyond the corner leash: the walk goes on
    if (best_index >= -1 && c.residual_grey >= tried[static_cast<std::size_t>(best_index + 1)]->residual_grey) return Fit::Worse;
    best_index = k;
    return Fit::Better;
  };
  const int start = last_exposure_ >= 0 ? last_exposure_ : -1;
  evaluate(start);
  bool improved_up = false;
  for (int k = start + 1; k < kCount; ++k) {
    const Fit f = evaluate(k);
    if (f == Fit::Worse) break;
    improved_up = improved_up || f == Fit::Better;
  }
  if (!improved_up) {
    for (int k = start - 1; k >= -1; --k) {
      if (evaluate(k) == Fit::Worse) break;
    }
  }
  if (best_index < -1) {  // nothing refined: the unblurred refinement says why
    last_exposure_ = -1;
    if (!tried[0]) evaluate(-1);
    return *tried[0];
  }
  last_exposure_ = best_index;
  if (best_index >= 0) blur_px = kExposureFractions[static_cast<std::size_t>(best_index)] * motion_px;
  return *tried[static_cast<std::size_t>(best_index + 1)];
}

bool PlanarObjectLocalizer::refine_pose(const cv::Mat& image, PlanarPose& pose, double size_px, double margin,
                                        PlanarResult& r) {
  r.pose_refined = false;
  if (config_.pose_refinement == PoseRefinement::Se3) {
    // The footprint model (raw frame, no smoothing) while no motion blur is modelled and the panel is
    // narrow enough; its residuals are not comparable with the sampled model's, so one frame uses one.
    const double width_px = camera_.intrinsics().fx * template_.width_m() / std::max(1e-3, pose.T_cam_object.translation().z());
    const bool use_footprint = footprint_refiner_.has_value() && width_px <= config_.se3_footprint_max_width_px &&
                               !(panel_motion_px(pose.T_cam_object, r.t).norm() >= kMinBlurMotionPx);
    if (use_footprint) {
      footprint_refiner_->select(raw_, pose.T_cam_object);  // the pixels every refinement below fits
    } else {
      if (pose.alternative_plausible) {
        pose_refiner_.smooth(image, {pose.T_cam_object, pose.T_alternative}, smoothed_);
      } else {
        pose_refiner_.smooth(image, {pose.T_cam_object}, smoothed_);
      }
    }
    Eigen::Vector2d blur_px = Eigen::Vector2d::Zero();
    Se3Refinement refined = refine_with_blur_search(pose.T_cam_object, r.t, use_footprint, blur_px, r.refinement_iterations);
    if (pose.alternative_plausible) {
      // Two distinct IPPE poses fit the corners: the photometric fit sees the perspective that tells
      // them apart. Both are refined; the lower residual wins when they end together or when its
      // residual is clearly lower (kUnresolvedResidualRatio), and the ambiguity is resolved unless the
      // residuals are within 2 % (then IPPE's flag stands).
      // Otherwise the two refined branches are the two minima of a photometric cost that cannot tell
      // them apart: a panel seen nearly face-on at range, whose tilt changes its image only to second
      // order, so a small bias in its apparent aspect ratio splits the minimum into two mirror poses on
      // either side of the truth (the simulated lab's oscilloscope at 2.6-3 m: the two branches 5-11 deg
      // apart, one 3-6 deg off either way). The pose is then the midway between them (rotation and
      // translation), within half their angle of either; the rotation sigma covers the whole angle.
      const Se3Refinement other = refine_once(pose.T_alternative, use_footprint, blur_px);
      r.refinement_iterations += other.iterations;
      bool two_minima = false;
      if (refined.refined && other.refined) {
        const double branch_angle = rotation_angle(refined.T_cam_object.linear(), other.T_cam_object.linear());
        const bool apart = branch_angle > kDistinctPosesRad;
        two_minima = apart;
        const double low = std::min(refined.residual_grey, other.residual_grey);
        const double high = std::max(refined.residual_grey, other.residual_grey);
        if (!apart || high >= 1.02 * low) pose.ambiguous = false;
        if (apart && high < kUnresolvedResidualRatio * low) {
          refined = midway(refined, other);
          refined.rotation_sigma_rad = std::max(refined.rotation_sigma_rad, branch_angle);
        } else if (other.residual_grey < refined.residual_grey) {
          refined = other;
        }
      } else if (other.refined) {
        refined = other;
      }
      // Both branches may also end in the same one of the two mirror minima (the lab's oscilloscope at
      // 2-3 m: both 3-4 deg off): the refined pose mirrored about the line of sight to the panel's
      // centre is refined too, and treated as the other branch above. Not with the footprint model,
      // whose cost has no such split minimum: on the bench's sequences the mirror does not change its
      // pose (docs/planar.md, "the pixel's footprint"), and it would cost a third of the refinement
      // work.
      // Test "planar: the mirror of the refined pose finds the other minimum both IPPE branches missed".
      if (refined.refined && !two_minima && !use_footprint) {
        const Eigen::Isometry3d T_mirror = mirrored_about_line_of_sight(refined.T_cam_object);
        if (rotation_angle(T_mirror.linear(), refined.T_cam_object.linear()) > kDistinctPosesRad) {
          const Se3Refinement mirror = refine_once(T_mirror, use_footprint, blur_px);
          r.refinement_iterations += mirror.iterations;
          const double angle = rotation_angle(mirror.T_cam_object.linear(), refined.T_cam_object.linear());
          if (mirror.refined && angle > kDistinctPosesRad) {
            const double low = std::min(refined.residual_grey, mirror.residual_grey);
            const double high = std::max(refined.residual_grey, mirror.residual_grey);
            if (high < kUnresolvedResidualRatio * low) {
              const double sigma = std::max({refined.rotation_sigma_rad, mirror.rotation_sigma_rad, angle});
              refined = midway(refined, mirror);
              refined.rotation_sigma_rad = sigma;
            } else if (mirror.residual_grey < refined.residual_grey) {
              refined = mirror;
            }
          }
        }
      }
    }
    if (refined.refined) {
      pose.T_cam_object = refined.T_cam_object;
      r.pose_refined = true;
      r.footprint_model = use_footprint;
      r.position_sigma_m = refined.position_sigma_m;
      r.rotation_sigma_rad = refined.rotation_sigma_rad;
      return true;
    }
    if (refined.contradicts_start) return false;
  }
  // From the corners alone, with a corner noise growing as the correlation margin shrinks (0.3 px when
  // aligned perfectly): depth from the apparent size, sigma_Z = Z sigma_px / size_px; the tilt of a
  // panel seen face-on changes its aspect ratio only to second order, so an aspect error sigma_px /
  // size_px reads as a tilt of sqrt(2 sigma_px / size_px) (IPPE; an upper bound when seen obliquely).
  const double sigma_px = 0.3 / std::max(0.1, margin);
  const double distance = pose.T_cam_object.translation().norm();
  r.position_sigma_m = distance * sigma_px / std::max(1.0, size_px);
  r.rotation_sigma_rad = std::sqrt(2.0 * sigma_px / std::max(1.0, size_px));
  return true;
}

}  // namespace labo::planar
