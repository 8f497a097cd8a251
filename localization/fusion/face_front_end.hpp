#pragma once
// The teacher's face in the front camera: FacePoseEstimator (localization/face/, the paper's §5:
// detection, 68 landmarks, the person's CANDIDE-3 shape, PnP) reported as a TargetObservation with
// the 68 landmarks as image points. face/ puts the face frame's z out of the face (towards a viewer);
// control's convention is z into the target, so the pose is turned about y here (flip_about_y()).
// Between posed faces (the teacher turned or walked away) the head is followed (HeadTracker) and
// reported as tracking with `position_only`: where the teacher is, not where they look.
#include <memory>
#include <mutex>
#include <optional>

#include "localization/fusion/vision_front_end.hpp"
#include "localization/face/face_pose_estimator.hpp"
#include "localization/face/head_tracker.hpp"

namespace labo::fusion {

class FaceFrontEnd final : public TargetFrontEnd {
 public:
  explicit FaceFrontEnd(std::unique_ptr<face::FacePoseEstimator> estimator);

  const TargetObservation& process(const cv::Mat& gray, Seconds t, std::optional<double> expected_distance_m) override;
  void reset() override;

  // The registered person to follow from the next frame on. Called from the flight thread while
  // process() may run on the vision worker: the shape waits here and process() takes it before its
  // frame (the estimator is never touched from two threads), and the track restarts with it.
  void follow(const face::PersonShape& person);

  const face::FaceResult& last_result() const { return result_; }
  const std::optional<face::HeadObservation>& last_head() const { return head_; }
  face::FacePoseEstimator& estimator() { return *estimator_; }

 private:
  std::string_view lost_reason() const;

  std::unique_ptr<face::FacePoseEstimator> estimator_;
  face::HeadTracker head_tracker_;
  face::FaceResult result_;
  std::optional<face::HeadObservation> head_;
  Eigen::Matrix3d R_cam_target_ = Eigen::Matrix3d::Identity();  // the last posed face's
  TargetObservation observation_;
  std::optional<Seconds> last_t_;
  std::mutex pending_mutex_;  // pending_person_
  std::optional<face::PersonShape> pending_person_;
};

}  // namespace labo::fusion
