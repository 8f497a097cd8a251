#pragma once
// The teacher-mode face pipeline of the paper's §5 (Fig. 4): detect the face (around the last one
// first), 68 landmarks, the rigid subset against the person's CANDIDE-3 shape, PnP with the selected
// method. Bad input never yields a wild pose: the result is "lost" with its reason.
#include <Eigen/Geometry>
#include <optional>
#include <opencv2/core.hpp>
#include <string>
#include <string_view>

#include "core/camera_model.hpp"
#include "core/time.hpp"
#include "localization/face/face_config.hpp"
#include "localization/face/face_detector.hpp"
#include "localization/face/face_geometry.hpp"
#include "localization/face/face_landmark_model.hpp"
#include "localization/face/face_pose_solver.hpp"
#include "localization/face/frontal_view.hpp"
#include "localization/face/landmark_detector.hpp"
#include "localization/face/person_shape.hpp"

namespace labo::face {

enum class FaceState { Tracking, Lost };
enum class FaceLostReason {
  None,
  BadImage,             // empty, wrong type or size
  NoFace,               // the detector found none
  SeveralFaces,         // several, none of them the teacher or near the last track
  CutByBorder,          // landmarks at or beyond the image border
  TooSmall,             // interocular distance below the limit
  BeyondProfile,        // yaw or pitch beyond the limits
  InconsistentLandmarks,// the landmarks do not fit the face model
  NoPose,               // the PnP method found no pose in front of the camera
  ImplausibleDistance,  // outside [min, max] distance
  ImplausibleMotion,    // the face jumped or changed size between frames: the landmarks slid off it
  NotConfirmed,         // the detector no longer finds the face the landmarks follow
  TurnedAtStart,        // a new track's first face turned beyond max_start_yaw: its pose is biased
};
std::string_view to_string(FaceState state);
std::string_view to_string(FaceLostReason reason);

struct FaceTimings {
  double detect_ms = 0, landmarks_ms = 0, pose_ms = 0;
  double total_ms() const { return detect_ms + landmarks_ms + pose_ms; }
};

struct FaceResult {
  Seconds t = 0;
  FaceState state = FaceState::Lost;
  FaceLostReason reason = FaceLostReason::NoFace;
  Eigen::Isometry3d T_cam_face = Eigen::Isometry3d::Identity();  // valid when tracking
  HeadAngles angles;                                             // of T_cam_face
  Eigen::Vector3d line_of_sight_cam = Eigen::Vector3d(0, 0, -1); // the face's +z in the camera
  Eigen::Matrix2Xd landmarks;         // 68 image pixels as detected (empty when no face was found)
  cv::Rect2d box;                     // the box the landmarks were run on
  double quality = 0;                 // 1 perfect fit, 0 at the consistency limit
  double reprojection_rms_px = 0;     // rigid landmarks, undistorted pixels
  int faces_found = 0;                // by the detector this frame (-1 when it did not run)
  bool reinitialised = false;         // LM tracking fell back to EPnP
  bool restarted = false;             // a tracked frame's landmarks did not fit: made again as a track's first
  Eigen::VectorXd landmark_weights;   // per model landmark, as used by the pose refinement (empty: equal)
  FaceTimings timings;

  bool tracking() const { return state == FaceState::Tracking; }
};

class FacePoseEstimator {
 public:
  // Loads the shape predictor, CANDIDE-3 and the mapping from `config` (throws std::runtime_error
  // naming the file on failure), and the registered teacher's shape when `config.teacher` is set.
  FacePoseEstimator(const FaceConfig& config, const PinholeCamera& camera);
  // For callers that already hold the landmark model (benchmarks, tests).
  FacePoseEstimator(const FaceConfig& config, const PinholeCamera& camera, FaceLandmarkModel model);

  // One grey frame (the camera's size) stamped `t`.
  FaceResult process(const cv::Mat& gray, Seconds t);
  // Forget the track (e.g. the drone turned away on purpose) and start the full-frame search over.
  void reset();
  // The next frame without a track searches for a face in and around `box` only (where the head was
  // followed), not the whole frame.
  void search_near(const cv::Rect2d& box) { search_hint_ = box; }
  const PinholeCamera& camera() const { return camera_; }

  // The person whose shape is used; `registered` marks them as the teacher to follow among several.
  void set_person(const PersonShape& person, bool registered);
  const PersonShape& person() const { return person_; }
  bool person_registered() const { return person_registered_; }
  const FaceLandmarkModel& model() const { return model_; }
  const FaceConfig& config() const { return config_; }
  PnpMethod method() const { return solver_.method(); }
  // Undistorted pixels of the model's landmarks from 68 image landmarks.
  Eigen::Matrix2Xd ideal_pixels(const Eigen::Matrix2Xd& landmarks68) const;
  IdealPinhole ideal_camera() const;

  // The faces' boxes in a whole picture (registration, tests): the full-frame search at every scale.
  std::vector<FaceBox> find_faces(const cv::Mat& gray);
  Eigen::Matrix2Xd landmarks_in(const cv::Mat& gray, const cv::Rect2d& box);
  // A detector's box made the predictor's own: LandmarkDetector::box_for on the landmarks found in
  // it. The HOG detector's box of one face varies by ±20 % in size from frame to frame and scale to
  // scale; from a box too large the predictor stretches the mouth and chin below the face (on the
  // face gallery's registration frames: the mouth 17 mm low, the registered person pitched 25°).
  // `box` itself when the landmarks found in it give no box inside the picture.
  cv::Rect2d settled_box(const cv::Mat& gray, const cv::Rect2d& box);
  // The 68 landmarks tracking would find for the face in detector box `box` seen at `T_cam_face`: the
  // predictor on the frontal view made at that pose through the current person's mesh, mapped back to
  // the image (registration, so that the person's points are where tracking's landmarks lie). Empty
  // when the frontal view is off or cannot be made there. Sets the detector box's relation, as a
  // track's first frame does: reset() before tracking.
  std::optional<Eigen::Matrix2Xd> landmarks_in_frontal_view(const cv::Mat& gray, const cv::Rect2d& box,
                                                            const Eigen::Isometry3d& T_cam_face);

 private:
  struct Candidate {
    cv::Rect2d box;
    bool from_detector = false;
  };
  std::optional<Candidate> choose_box(const cv::Mat& gray, FaceResult& result);
  std::optional<Candidate> select_among(const cv::Mat& gray, const std::vector<FaceBox>& boxes, FaceResult& result);
  FaceResult lose(FaceResult result, FaceLostReason reason);
  void remember_box_relation(const cv::Rect2d& box, const Eigen::Matrix2Xd& landmarks, double distance_m);
  cv::Rect2d box_from_landmarks(const Eigen::Matrix2Xd& landmarks) const;
  double interocular_px(const Eigen::Matrix2Xd& landmarks68) const;
  void set_landmark_weights(PnpProblem& problem) const;
  void detect_landmarks(const cv::Mat& gray, const Candidate& candidate, Eigen::Matrix2Xd& lm);
  // The candidate's landmarks, their checks and the pose they give (into `estimate`); the result's
  // landmarks, weights, reprojection RMS and stage times filled in. None when they serve, else why not.
  FaceLostReason pose_landmarks(const cv::Mat& gray, const Candidate& candidate, FaceResult& result, Eigen::Matrix2Xd& lm,
                                std::optional<FacePoseEstimate>& estimate);
  // The landmarks found on a frontal view of the face made at `T_cam_face` (moved by `shift` px);
  // false (lm and view_weights_ untouched) when the view is off or cannot be made for this candidate.
  // On a track's first frame (`start`) a turned face's far side is mirrored (start_mirror_yaw) and
  // view_weights_ set; otherwise view_weights_ is cleared.
  bool detect_in_frontal_view(const cv::Mat& gray, const Candidate& candidate, const Eigen::Isometry3d& T_cam_face,
                              const Eigen::Vector2d& shift, Eigen::Matrix2Xd& lm, bool start = false);
  // The frontal view with its far side (for a face turned by `yaw`) blended with the near side's
  // mirror image, `mirror` (0-1) at most; sets view_weights_.
  const cv::Mat& mirror_far_side(double yaw, double mirror, double view_px_per_m);
  // EPnP + LM of the person's points to `lm` (68 image landmarks), outside the tracking solver.
  std::optional<PnpSolution> fit_pose(const Eigen::Matrix2Xd& lm, const Eigen::VectorXd& weights = {}) const;
  bool plausible_distance(const PnpSolution& s) const;

  FaceConfig config_;
  PinholeCamera camera_;
  FaceLandmarkModel model_;
  FaceDetector detector_;
  LandmarkDetector landmark_detector_;
  FacePoseSolver solver_;
  PersonShape person_;
  bool person_registered_ = false;
  Eigen::Matrix3Xd points_face_;  // the person's rigid landmarks, metres
  Eigen::VectorXd noise_weights_;  // per landmark, from the noise model (empty when it is off)
  std::optional<Candide3Model> candide_;  // the mesh, when the frontal view is on
  std::optional<FrontalView> frontal_;
  Eigen::Matrix2Xd view_landmarks_;       // reused buffer
  cv::Mat flipped_, mirrored_;            // reused buffers (a track's first frame only)
  Eigen::VectorXd view_weights_;          // per model landmark, from the last view (empty: equal)
  Eigen::Matrix2Xd start_lm_;             // reused buffer

  // Track state.
  std::optional<Eigen::Matrix2Xd> last_landmarks_;
  std::optional<Eigen::Vector2d> landmark_velocity_px_;
  std::optional<cv::Rect2d> last_box_;
  Eigen::Matrix2Xd settle_lm_;  // settled_box's landmarks: a buffer, kept to not allocate per detection
  std::optional<cv::Rect2d> search_hint_;  // one frame's
  int frames_since_detection_ = 0;
  int lost_frames_ = 0;
  std::size_t lost_search_cycle_ = 0;
  // The detector's box relative to its landmarks: centre offset (in box sides) and its metric size
  // (side x distance / fx, which does not change when the head turns, unlike the landmarks' spread).
  Eigen::Vector2d box_offset_ = Eigen::Vector2d(0, 0.1);
  double box_side_m_ = 0.2;
  bool box_relation_measured_ = false;  // this frame, by the first frame's frontal pass
  std::optional<Eigen::Isometry3d> last_pose_;
  double last_spread_px_ = 0;
  int detector_misses_ = 0;
  PnpProblem problem_;  // reused buffers
};

}  // namespace labo::face
