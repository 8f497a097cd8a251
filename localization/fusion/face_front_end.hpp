#pragma once
// The teacher's face in the front camera: FacePoseEstimator (localization/face/, the paper's §5:
// detection, 68 landmarks, the person's CANDIDE-3 shape, PnP) reported as a TargetObservation with
// the 68 landmarks as image points. face/ puts the face frame's z out of the face (towards a viewer);
// control's convention is z into the target, so the pose is turned about y here (flip_about_y()).
#include <memory>
#include <optional>

#include "localization/fusion/vision_front_end.hpp"
#include "localization/face/face_pose_estimator.hpp"

namespace labo::fusion {

class FaceFrontEnd final : public TargetFrontEnd {
 public:
  explicit FaceFrontEnd(std::unique_ptr<face::FacePoseEstimator> estimator);

  const TargetObservation& process(const cv::Mat& gray, Seconds t, std::optional<double> expected_distance_m) override;
  void reset() override;

  const face::FaceResult& last_result() const { return result_; }
  face::FacePoseEstimator& estimator() { return *estimator_; }

 private:
  std::unique_ptr<face::FacePoseEstimator> estimator_;
  face::FaceResult result_;
  TargetObservation observation_;
  std::optional<Seconds> last_t_;
};

}  // namespace labo::fusion
