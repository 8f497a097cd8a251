#include "localization/face/teacher_head.hpp"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

#include "core/candide3.hpp"
#include "localization/face/face_pose_estimator.hpp"
#include "localization/face/textured_head_renderer.hpp"

namespace labo::face {

using lab::LabDescription;


TexturedHeadModel to_head_model(const Candide3Model& candide, const TexturedHead& head, const cv::Mat& photo_bgr) {
  TexturedHeadModel model;
  model.vertices_face_m = head_vertices_m(candide, head);
  model.triangles = candide.triangles();
  for (Eigen::Index v = 0; v < head.uv.cols(); ++v) model.texture_px.push_back(head.uv.col(v).cast<float>());
  model.texture_bgr = photo_bgr;
  validate(model);
  return model;
}

TexturedHeadModel load_teacher_head(const std::filesystem::path& photo_path, double ipd_m, const FaceConfig& base) {
  if (!(ipd_m >= 0.04 && ipd_m <= 0.09)) {
    throw std::invalid_argument("teacher head: interpupillary distance " + std::to_string(ipd_m) +
                                " m outside the human range 0.04-0.09 m");
  }
  const cv::Mat photo = cv::imread(photo_path.string(), cv::IMREAD_COLOR);
  if (photo.empty()) {
    throw std::runtime_error("teacher head: cannot read the photograph " + photo_path.string() +
                             (std::filesystem::exists(photo_path) ? " (not a decodable image)"
                                                                   : " (no such file; scripts/setup.sh extracts assets/astronaut.png)"));
  }
  cv::Mat gray;
  cv::cvtColor(photo, gray, cv::COLOR_BGR2GRAY);
  FaceConfig config = base;
  config.teacher.clear();
  const Candide3Model candide = Candide3Model::load(config.model);
  // The estimator needs a camera only for tracking; the photograph's own portrait lens is inside
  // texture_head_from_photo.
  const double f = 1.5 * photo.cols;
  const PinholeCamera camera({photo.cols, photo.rows, f, f, photo.cols / 2.0, photo.rows / 2.0});
  FacePoseEstimator estimator(config, camera, make_face_landmark_model(candide, load_ibug68_mapping(config.mapping)));
  TexturedHead head;
  try {
    head = texture_head_from_photo(estimator, candide, gray, ipd_m);
  } catch (const std::runtime_error& e) {
    throw std::runtime_error(photo_path.string() + ": " + e.what());
  }
  return to_head_model(candide, head, photo);
}

TexturedHeadModel load_lab_teacher_head(const LabDescription& lab, const FaceConfig& config) {
  std::filesystem::path photo = lab.teacher.face_image;
  if (photo.is_relative()) photo = (lab.source.parent_path() / photo).lexically_normal();
  return load_teacher_head(photo, lab.teacher.interpupillary_distance_m, config);
}

}  // namespace labo::face
