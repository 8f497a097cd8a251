#pragma once
// The teacher's head followed in the image while their face cannot be posed: turned away, in
// profile, or beyond the landmarks' reach. The face pipeline (FacePoseEstimator) needs a face within
// ~35-45 degrees of frontal; a teacher who turns or walks away would be lost and found again only by
// a search. The head's outline and shading change slowly from frame to frame whichever way it turns,
// so its image patch, learnt on frames where the face is posed, is matched (normalised correlation,
// three scales) around where it was and adapted as it turns. It gives where the head is (a ray and a
// distance from the patch's scale), never how it is turned, and only for a bounded time after the
// last posed face: a template left to adapt long enough drifts onto the background.
#include <Eigen/Geometry>
#include <optional>
#include <opencv2/core.hpp>
#include <string_view>

#include "core/camera_model.hpp"
#include "core/time.hpp"

namespace labo::face {

struct HeadTrackerOptions {
  double head_width_m = 0.20;   // the patch: the head's outline with a little background round it
  double head_height_m = 0.26;
  double centre_behind_face_m = 0.09;  // the head's centre behind the face model's origin
  double min_score = 0.55;      // normalised correlation below which the head is lost
  Seconds max_follow_s = 20.0;  // since the last posed face
  double adapt_rate = 0.05;     // of each matched patch blended into the template
  double search_margin = 0.6;   // of the box's width, on every side of the last box
  double scale_step = 0.04;     // the scales tried each frame: 1 - step, 1, 1 + step
  double scale_change_cost = 0.02;  // of correlation, against a change of scale
  double min_distance_m = 0.3, max_distance_m = 6.0;
  double max_height_fraction = 0.8;  // of the image's height
  double border_margin = 0.25;       // of the box's width: the box's centre this far inside the image
  // A head lost (no longer matching where it was, at the border, or the video dropped for a while)
  // is looked for again for this long after, with its template as it was: near where it was lost
  // (1.5 box heights) at about its size (within 18 %), and better than the frame to frame match
  // (more places offer more chances of a look-alike).
  Seconds reacquire_s = 8.0;
  double reacquire_min_score = 0.72;
};

// Why no head is followed: shown with the face's reason, and what a campaign's traces are read by.
enum class HeadLostReason {
  None,           // followed
  NotLearnt,      // no posed face since the tracker was reset
  FaceTooLongAgo, // followed for max_follow_s since the last posed face
  NoMatch,        // the best correlation below min_score
  AtBorder,       // the head's centre too near the image's border
  FillsImage,     // the head taller than max_height_fraction of the image
  ImplausibleDistance,  // the distance from the box's size outside [min, max]
  RegionTooSmall, // the search region, clipped by the image, smaller than the template
  FrameGap,       // frames stopped coming for a while (the video link dropped)
};
std::string_view to_string(HeadLostReason reason);

struct HeadObservation {
  Eigen::Vector3d p_cam_head_m = Eigen::Vector3d::Zero();  // the head's centre in the camera
  cv::Rect2d box;         // its patch in the image
  double score = 0;       // normalised correlation of the match
  Seconds since_face_s = 0;
  bool reacquired = false;  // found again after a loss (this frame)
};

class HeadTracker {
 public:
  explicit HeadTracker(const PinholeCamera& camera, HeadTrackerOptions options = {});

  // A frame whose face was posed at `T_cam_face` (face/ convention: z out of the face): the head's
  // patch and size are learnt from it.
  void learn(const cv::Mat& gray, const Eigen::Isometry3d& T_cam_face, Seconds t);
  // A frame without a posed face: the head near where it was last, or nullopt (nothing learnt, too
  // long since the last face, no good match, or out of the image: lost_reason() says which). A lost
  // head is looked for round where it was for reacquire_s, then stays lost until learn().
  std::optional<HeadObservation> follow(const cv::Mat& gray, Seconds t);
  void reset();
  // Frames stopped coming until `t` (the video link dropped): the head may have moved in the image,
  // so it is lost, with its template kept and looked for round where it was from the next frame.
  void interrupt(Seconds t);
  bool active() const { return box_.has_value(); }  // learnt, and not lost since
  // Why the head is not followed (None while it is); kept until the next learn().
  HeadLostReason lost_reason() const { return lost_reason_; }
  const HeadTrackerOptions& options() const { return options_; }

 private:
  bool take_patch(const cv::Mat& gray, const cv::Rect2d& box, cv::Mat& out);
  // The template from the last posed face's pixels, when learn() has left it to be made.
  void make_template_if_stale();
  // Lost: the template is kept for reacquire() when `keep_template`.
  std::nullopt_t lose(HeadLostReason reason, Seconds t, bool keep_template = true);
  struct Match {
    cv::Rect2d box;
    double score = 0;  // normalised correlation
  };
  // The kept template's best match round where it was lost; nullopt when nothing matches well
  // enough.
  std::optional<Match> reacquire(const cv::Mat& gray);
  // The head's box in this frame near `last` (the frame to frame match); nullopt (and lost_reason_
  // set) when it no longer matches.
  std::optional<Match> match_near(const cv::Mat& gray, const cv::Rect2d& last);
  // The head's place from its box (through the lens model), or nullopt when the box is not a head
  // to follow (at the border, filling the image, at an implausible distance); sets lost_reason_.
  std::optional<Eigen::Vector3d> place_of(const cv::Rect2d& box, const cv::Mat& gray);

  PinholeCamera camera_;
  HeadTrackerOptions options_;
  std::optional<cv::Rect2d> box_;  // the head's patch in the last frame it was seen
  cv::Mat face_pixels_;             // the last posed face's head patch, at its top left
  cv::Size face_patch_size_;
  bool template_stale_ = false;    // the template is still to be made from face_pixels_
  cv::Mat template_;               // CV_32F, the template's size
  Seconds last_face_t_ = 0;
  HeadLostReason lost_reason_ = HeadLostReason::NotLearnt;
  std::optional<cv::Rect2d> lost_box_;  // the last box before a loss whose template is kept
  Seconds lost_t_ = 0;
  // Reused buffers.
  cv::Mat region_8u_, region_, scaled_template_, scores_, patch_8u_, patch_;
};

}  // namespace labo::face
