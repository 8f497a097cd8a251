#pragma once
// The teacher's face in the front camera: FacePoseEstimator (localization/face/, the paper's §5:
// detection, 68 landmarks, the person's CANDIDE-3 shape, PnP) reported as a TargetObservation with
// the 68 landmarks as image points. face/ puts the face frame's z out of the face (towards a viewer);
// control's convention is z into the target, so the pose is turned about y here (flip_about_y()).
#include <memory>
#include <mutex>
#include <optional>

#include "localization/fusion/vision_front_end.hpp"
#include "localization/face/face_pose_estimator.hpp"

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
  face::FacePoseEstimator& estimator() { return *estimator_; }

 private:
  std::unique_ptr<face::FacePoseEstimator> estimator_;
  face::FaceResult result_;
  TargetObservation observation_;
  std::optional<Seconds> last_t_;
  std::mutex pending_mutex_;  // pending_person_
  std::optional<face::PersonShape> pending_person_;
};

}  // namespace labo::fusion
