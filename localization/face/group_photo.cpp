#include "localization/face/group_photo.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

namespace labo::face {

namespace {

// Left to right by the box's centre, top to bottom within a column: an order that needs no guess at
// where a photograph's rows are.
bool reads_before(const FaceBox& a, const FaceBox& b) {
  const double ax = a.box.x + a.box.width / 2, bx = b.box.x + b.box.width / 2;
  if (ax != bx) return ax < bx;
  return a.box.y < b.box.y;
}

}  // namespace

std::vector<GroupPortrait> portraits_in_group_photo(FacePoseEstimator& estimator, const cv::Mat& photo_bgr,
                                                    const GroupCropOptions& options) {
  if (photo_bgr.empty() || photo_bgr.type() != CV_8UC3) {
    throw std::invalid_argument("group photograph: expected a non-empty 8-bit colour picture");
  }
  cv::Mat gray;
  cv::cvtColor(photo_bgr, gray, cv::COLOR_BGR2GRAY);
  std::vector<FaceBox> faces = estimator.find_faces(gray);
  std::sort(faces.begin(), faces.end(), reads_before);
  const PortraitLimits limits = portrait_limits(estimator.config());
  std::vector<GroupPortrait> portraits;
  for (std::size_t i = 0; i < faces.size(); ++i) {
    const Eigen::Matrix2Xd lm = estimator.landmarks_in(gray, faces[i].box);
    const Eigen::Vector2d centre = lm.middleCols(17, 43).rowwise().mean();
    const double side = options.side_interocular * interocular_px(lm);
    const cv::Rect wanted(cvRound(centre.x() - side / 2), cvRound(centre.y() - side / 2), cvRound(side), cvRound(side));
    const cv::Rect inside = wanted & cv::Rect(0, 0, photo_bgr.cols, photo_bgr.rows);
    char name[64];
    std::snprintf(name, sizeof name, "%s_%02zu", options.prefix.c_str(), i + 1);
    GroupPortrait p{name, faces[i].box, photo_bgr(inside).clone(), {}};
    cv::Mat crop_gray;
    cv::cvtColor(p.crop_bgr, crop_gray, cv::COLOR_BGR2GRAY);
    p.face = find_portrait_face(estimator, crop_gray, limits);
    portraits.push_back(std::move(p));
  }
  return portraits;
}

}  // namespace labo::face
