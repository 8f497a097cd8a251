#pragma once
// Portraits cut from a group photograph (the face benchmark's people, the simulated teacher's faces):
// every face the detector finds, cropped around its landmarks, so that no face is chosen or placed by
// hand. Each crop is then examined as a portrait on its own (portrait.hpp): a neighbour's face inside
// the crop, a small or cut face is refused with its reason rather than dropped silently.
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "localization/face/face_pose_estimator.hpp"
#include "localization/face/portrait.hpp"

namespace labo::face {

struct GroupPortrait {
  std::string name;     // "<prefix>_NN", NN the face's rank left to right (then top to bottom) from 01
  cv::Rect2d box;       // the detector's box in the group photograph
  cv::Mat crop_bgr;     // the square crop, colour as the photograph
  PortraitFace face;    // the crop examined as a portrait (its refusal and reason, if any)
};

struct GroupCropOptions {
  // The crop's side in interocular distances: the CANDIDE-3 mesh spans about 3.3 of them from chin
  // to forehead; more takes in neighbours' faces.
  double side_interocular = 4.0;
  std::string prefix = "face";
};

// Throws std::invalid_argument for an empty or non-BGR photograph.
std::vector<GroupPortrait> portraits_in_group_photo(FacePoseEstimator& estimator, const cv::Mat& photo_bgr,
                                                    const GroupCropOptions& options = {});

}  // namespace labo::face
