#include "localization/face/head_tracker.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <opencv2/imgproc.hpp>

namespace labo::face {

namespace {
// The template's size: the search runs at this resolution (a few times coarser than the image at
// 1 m), yet it holds the head's outline and the face's or hair's shading (`bench vision`'s head_track).
const cv::Size kTemplateSize(30, 39);
// A lost head is looked for within this many box heights of where it was lost, at sizes up to this
// ratio of its last either way, in steps this far apart (~3 px of the template's height).
constexpr double kReacquireNearBoxes = 1.5;
constexpr double kReacquireNearScale = 1.18;
constexpr double kReacquireScaleStep = 1.08;

cv::Point2d centre(const cv::Rect2d& r) { return {r.x + r.width / 2, r.y + r.height / 2}; }

cv::Rect pixel_rect(const cv::Rect2d& box) {
  return {cv::Point(static_cast<int>(std::lround(box.x)), static_cast<int>(std::lround(box.y))),
          cv::Size(static_cast<int>(std::lround(box.width)), static_cast<int>(std::lround(box.height)))};
}

// A patch worth taking: a few pixels at least, and wholly inside the image.
bool whole_patch(const cv::Rect& r, const cv::Mat& gray) {
  return r.width >= 4 && r.height >= 4 && (r & cv::Rect(0, 0, gray.cols, gray.rows)) == r;
}
}  // namespace

std::string_view to_string(HeadLostReason reason) {
  switch (reason) {
    case HeadLostReason::None: return "none";
    case HeadLostReason::NotLearnt: return "no head learnt from a posed face";
    case HeadLostReason::FaceTooLongAgo: return "head followed too long since the last posed face";
    case HeadLostReason::NoMatch: return "head no longer matches its patch";
    case HeadLostReason::AtBorder: return "head at the image's border";
    case HeadLostReason::FillsImage: return "head fills the image";
    case HeadLostReason::ImplausibleDistance: return "head's distance implausible";
    case HeadLostReason::RegionTooSmall: return "head's search region cut by the image";
    case HeadLostReason::FrameGap: return "no frames for a while (video link)";
  }
  return "unknown";
}

HeadTracker::HeadTracker(const PinholeCamera& camera, HeadTrackerOptions options) : camera_(camera), options_(options) {}

void HeadTracker::reset() {
  box_.reset();
  lost_box_.reset();
  template_stale_ = false;
  face_patch_size_ = cv::Size();
  lost_reason_ = HeadLostReason::NotLearnt;
}

std::nullopt_t HeadTracker::lose(HeadLostReason reason, Seconds t, bool keep_template) {
  // A head lost on the frame after its posed face (the video dropped) is looked for with that face's
  // look, not with the template of the head followed before it.
  if (keep_template) make_template_if_stale();
  const std::optional<cv::Rect2d> last = box_;
  reset();
  lost_reason_ = reason;
  if (keep_template && last && !template_.empty()) {
    lost_box_ = last;
    lost_t_ = t;
  }
  return std::nullopt;
}

void HeadTracker::interrupt(Seconds t) {
  if (box_) lose(HeadLostReason::FrameGap, t);
}

void HeadTracker::make_template_if_stale() {
  if (!template_stale_ || face_patch_size_.area() == 0) return;
  cv::resize(face_pixels_(cv::Rect(cv::Point(0, 0), face_patch_size_)), patch_8u_, kTemplateSize, 0, 0, cv::INTER_AREA);
  patch_8u_.convertTo(template_, CV_32F);
  template_stale_ = false;
}

bool HeadTracker::take_patch(const cv::Mat& gray, const cv::Rect2d& box, cv::Mat& out) {
  const cv::Rect r = pixel_rect(box);
  if (!whole_patch(r, gray)) return false;
  cv::resize(gray(r), patch_8u_, kTemplateSize, 0, 0, cv::INTER_AREA);
  patch_8u_.convertTo(out, CV_32F);
  return true;
}

void HeadTracker::learn(const cv::Mat& gray, const Eigen::Isometry3d& T_cam_face, Seconds t) {
  if (gray.empty() || gray.type() != CV_8UC1) return;
  const Eigen::Vector3d head = T_cam_face * Eigen::Vector3d(0, 0, -options_.centre_behind_face_m);
  // The box through the lens model, as follow() measures the distance from it.
  const Eigen::Vector3d half_w(options_.head_width_m / 2, 0, 0), half_h(0, options_.head_height_m / 2, 0);
  const auto px = camera_.project(head);
  const auto left = camera_.project(head - half_w), right = camera_.project(head + half_w);
  const auto top = camera_.project(head - half_h), bottom = camera_.project(head + half_h);
  if (!px || !left || !right || !top || !bottom) return;
  const double w = right->x() - left->x(), h = bottom->y() - top->y();
  const cv::Rect2d box(px->x() - w / 2, px->y() - h / 2, w, h);
  // The patch is kept as pixels and made a template only when the face is lost: resampling it here
  // would allocate on every posed frame (OpenCV's area resampling builds its tables on the heap).
  // A head partly out of the image keeps the patch it had; the place is still the face's.
  const cv::Rect r = pixel_rect(box);
  if (whole_patch(r, gray)) {
    if (face_pixels_.size() != gray.size()) face_pixels_.create(gray.size(), CV_8UC1);
    cv::Mat into = face_pixels_(cv::Rect(cv::Point(0, 0), r.size()));
    gray(r).copyTo(into);
    face_patch_size_ = r.size();
  }
  if (face_patch_size_.area() == 0) return;
  template_stale_ = true;
  box_ = box;
  lost_box_.reset();
  last_face_t_ = t;
  lost_reason_ = HeadLostReason::None;
}

std::optional<HeadObservation> HeadTracker::follow(const cv::Mat& gray, Seconds t) {
  if (gray.empty() || gray.type() != CV_8UC1) return std::nullopt;
  if (!box_ && !lost_box_) return std::nullopt;
  if (t - last_face_t_ > options_.max_follow_s) return lose(HeadLostReason::FaceTooLongAgo, t, false);
  const bool reacquiring = !box_;
  if (reacquiring && t - lost_t_ > options_.reacquire_s) {
    lost_box_.reset();
    return std::nullopt;
  }
  make_template_if_stale();
  const HeadLostReason lost_for = lost_reason_;
  const std::optional<Match> match = reacquiring ? reacquire(gray) : match_near(gray, *box_);
  const std::optional<Eigen::Vector3d> place = match ? place_of(match->box, gray) : std::nullopt;
  if (!place) {
    if (!reacquiring) return lose(lost_reason_, t);
    // Not found, or not a head to follow: the loss stands as it was, the template kept.
    lost_reason_ = lost_for;
    return std::nullopt;
  }
  // The head turns under the template: follow its new look a little each frame.
  if (take_patch(gray, match->box, patch_)) cv::addWeighted(template_, 1.0 - options_.adapt_rate, patch_, options_.adapt_rate, 0.0, template_);
  box_ = match->box;
  lost_box_.reset();
  lost_reason_ = HeadLostReason::None;
  HeadObservation out;
  out.p_cam_head_m = *place;
  out.box = match->box;
  out.score = match->score;
  out.since_face_s = t - last_face_t_;
  out.reacquired = reacquiring;
  return out;
}

std::optional<HeadTracker::Match> HeadTracker::match_near(const cv::Mat& gray, const cv::Rect2d& last) {
  // The search runs at the template's resolution: the image scaled by 1/f.
  const double f = last.height / kTemplateSize.height;
  const double m = options_.search_margin * last.width;
  const cv::Rect region = cv::Rect(cv::Point(static_cast<int>(std::floor(last.x - m)), static_cast<int>(std::floor(last.y - m))),
                                   cv::Point(static_cast<int>(std::ceil(last.x + last.width + m)),
                                             static_cast<int>(std::ceil(last.y + last.height + m)))) &
                          cv::Rect(0, 0, gray.cols, gray.rows);
  const cv::Size scaled(static_cast<int>(std::lround(region.width / f)), static_cast<int>(std::lround(region.height / f)));
  if (scaled.width <= kTemplateSize.width || scaled.height <= kTemplateSize.height) {
    lost_reason_ = HeadLostReason::RegionTooSmall;
    return std::nullopt;
  }
  cv::resize(gray(region), region_8u_, scaled, 0, 0, f > 1 ? cv::INTER_AREA : cv::INTER_LINEAR);
  region_8u_.convertTo(region_, CV_32F);

  double best_score = -1, best_scale = 1;
  cv::Point best_at;
  const std::array<double, 3> scales{1.0 - options_.scale_step, 1.0, 1.0 + options_.scale_step};
  for (double s : scales) {
    const cv::Size size(static_cast<int>(std::lround(kTemplateSize.width * s)), static_cast<int>(std::lround(kTemplateSize.height * s)));
    if (size.width >= region_.cols || size.height >= region_.rows) continue;
    cv::resize(template_, scaled_template_, size, 0, 0, cv::INTER_LINEAR);
    cv::matchTemplate(region_, scaled_template_, scores_, cv::TM_CCOEFF_NORMED);
    double score = 0;
    cv::Point at;
    cv::minMaxLoc(scores_, nullptr, &score, nullptr, &at);
    // A change of scale must earn it: the correlation's peak is flat in scale, and an unbiased
    // choice lets the box's size (the distance) random-walk. Scaling width and height apart (a head
    // widens as it turns to its profile) was tried: the box stretched towards where the head had
    // been, and lagged a walking teacher by 0.2 m.
    if (s != 1.0) score -= options_.scale_change_cost;
    if (score > best_score) {
      best_score = score;
      best_scale = static_cast<double>(size.height) / kTemplateSize.height;
      best_at = at;
    }
  }
  if (best_score < options_.min_score) {
    lost_reason_ = HeadLostReason::NoMatch;
    return std::nullopt;
  }
  return Match{cv::Rect2d(region.x + best_at.x * f, region.y + best_at.y * f, last.width * best_scale, last.height * best_scale), best_score};
}

std::optional<HeadTracker::Match> HeadTracker::reacquire(const cv::Mat& gray) {
  const cv::Rect2d& last = *lost_box_;
  // Near where it was lost and at about its size only: a head is likelier there than a look-alike.
  // Over the whole frame at 0.63-1.59 of the size, the best match in the randomized lab was as often
  // a look-alike on a bench or a wall, and the drone followed it (docs/face.md); and after half a
  // second of dropped video the template shrunk to two thirds matched the collar below the head
  // better than the head.
  const double reach = (kReacquireNearBoxes + 0.6 * kReacquireNearScale) * last.height;
  const cv::Point2d c = centre(last);
  const cv::Rect area = cv::Rect(cv::Point(static_cast<int>(std::floor(c.x - reach)), static_cast<int>(std::floor(c.y - reach))),
                                 cv::Point(static_cast<int>(std::ceil(c.x + reach)), static_cast<int>(std::ceil(c.y + reach)))) &
                        cv::Rect(0, 0, gray.cols, gray.rows);
  // The area once at the last box's resolution; the template scaled over the sizes tried.
  const double f = last.height / kTemplateSize.height;
  const cv::Size scaled(static_cast<int>(std::lround(area.width / f)), static_cast<int>(std::lround(area.height / f)));
  if (scaled.width <= kTemplateSize.width || scaled.height <= kTemplateSize.height) return std::nullopt;
  cv::resize(gray(area), region_8u_, scaled, 0, 0, f > 1 ? cv::INTER_AREA : cv::INTER_LINEAR);
  region_8u_.convertTo(region_, CV_32F);
  const cv::Point2d last_centre = (c - cv::Point2d(area.x, area.y)) / f;
  const double near_radius = kReacquireNearBoxes * kTemplateSize.height;
  double best_score = -1, best_scale = 1;
  cv::Point best_at;
  // Powers of the step, so that the last box's own size is among them.
  const int k_max = static_cast<int>(std::floor(std::log(kReacquireNearScale) / std::log(kReacquireScaleStep) + 1e-9));
  for (int k = -k_max; k <= k_max; ++k) {
    const double s = std::pow(kReacquireScaleStep, k);
    const cv::Size size(static_cast<int>(std::lround(kTemplateSize.width * s)), static_cast<int>(std::lround(kTemplateSize.height * s)));
    if (size.width >= region_.cols || size.height >= region_.rows) break;
    // Rounded to the template's pixels, a size may fall beyond the ratio (1.08^-2: 33/39 px).
    const double scale = static_cast<double>(size.height) / kTemplateSize.height;
    if (std::abs(std::log(scale)) > std::log(kReacquireNearScale) + 1e-9) continue;
    if (k == 0) template_.copyTo(scaled_template_);
    else cv::resize(template_, scaled_template_, size, 0, 0, s < 1 ? cv::INTER_AREA : cv::INTER_LINEAR);
    cv::matchTemplate(region_, scaled_template_, scores_, cv::TM_CCOEFF_NORMED);
    // The top-left corners whose box centre is within near_radius of the last one.
    const cv::Point2d corner = last_centre - cv::Point2d(size.width / 2.0, size.height / 2.0);
    const cv::Rect window = cv::Rect(cv::Point(static_cast<int>(std::floor(corner.x - near_radius)), static_cast<int>(std::floor(corner.y - near_radius))),
                                     cv::Point(static_cast<int>(std::ceil(corner.x + near_radius)) + 1, static_cast<int>(std::ceil(corner.y + near_radius)) + 1)) &
                            cv::Rect(0, 0, scores_.cols, scores_.rows);
    if (window.area() == 0) continue;
    double score = 0;
    cv::Point at;
    cv::minMaxLoc(scores_(window), nullptr, &score, nullptr, &at);
    if (score > best_score) {
      best_score = score;
      best_scale = scale;
      best_at = at + window.tl();
    }
  }
  if (best_score < options_.reacquire_min_score) return std::nullopt;
  return Match{cv::Rect2d(area.x + best_at.x * f, area.y + best_at.y * f, last.width * best_scale, last.height * best_scale), best_score};
}

std::optional<Eigen::Vector3d> HeadTracker::place_of(const cv::Rect2d& box, const cv::Mat& gray) {
  const cv::Point2d c = centre(box);
  // A head filling the frame (the drone at arm's length) or leaving it has no outline left to match.
  if (!camera_.in_image({c.x, c.y}, options_.border_margin * box.width)) {
    lost_reason_ = HeadLostReason::AtBorder;
    return std::nullopt;
  }
  if (box.height > options_.max_height_fraction * gray.rows) {
    lost_reason_ = HeadLostReason::FillsImage;
    return std::nullopt;
  }
  // The distance from the angle the box's height spans (through the lens model: at the image's edge
  // the AR.Drone's wide lens shrinks a head by a fifth).
  const Eigen::Vector3d top = camera_.unproject({c.x, box.y});
  const Eigen::Vector3d bottom = camera_.unproject({c.x, box.y + box.height});
  const double angle = std::acos(std::clamp(top.dot(bottom), -1.0, 1.0));
  const double distance = options_.head_height_m / (2.0 * std::tan(angle / 2.0));
  if (!(distance >= options_.min_distance_m && distance <= options_.max_distance_m)) {
    lost_reason_ = HeadLostReason::ImplausibleDistance;
    return std::nullopt;
  }
  return camera_.unproject({c.x, c.y}) * distance;
}

}  // namespace labo::face
