#pragma once
// Renders the CANDIDE-3 head textured with a photograph, for the face benchmark and tests: the
// photograph's face is located with the same detector and landmarks the estimator uses, CANDIDE-3 is
// fitted to it (shape and pose), and every vertex takes the photograph's pixel under it as texture
// coordinate. The head is then drawn at any pose through the real camera model, distortion included.
// (The simulated lab owns the lab-wide renderer; this one exists so the benchmark has a known
// ground truth without the rest of the lab.)
#include <Eigen/Geometry>
#include <opencv2/core.hpp>
#include <vector>

#include "core/camera_model.hpp"
#include "core/candide3.hpp"
#include "localization/face/face_pose_estimator.hpp"

namespace labo::face {

struct TexturedHead {
  cv::Mat texture;                 // 8-bit grey photograph
  Eigen::Matrix2Xd uv;             // texture pixel of each CANDIDE-3 vertex
  Eigen::VectorXd shape_params;    // fitted to the photograph
  double interpupillary_distance_m = 0.063;
  // On top of the shape's metric scale, so that the photograph's eyes (not the mesh's eye vertices)
  // are interpupillary_distance_m apart on the drawn head.
  double scale = 1.0;
  // Where the photograph's 68 landmarks lie on the textured mesh (face frame, metres; NaN where a
  // landmark falls on no triangle): the rendered head's true landmark positions, for the benchmark's
  // analysis of landmark errors apart from the model's.
  Eigen::Matrix3Xd landmarks_face_m;
};

// The photograph must serve as a portrait (portrait.hpp: one face, large enough, whole, within
// frontal_max_angle of frontal); otherwise throws std::runtime_error with the reason.
TexturedHead texture_head_from_photo(FacePoseEstimator& estimator, const Candide3Model& candide,
                                     const cv::Mat& photo_gray, double interpupillary_distance_m);

// The lens a portrait is taken to be seen through: centred, no distortion, the face 1.5 m away
// (`interocular_px` apart at `ipd_m`).
IdealPinhole portrait_lens(const cv::Size& size, double interocular_px, double ipd_m);

// The head's CANDIDE-3 vertices in the face frame, metres: the fitted shape at the estimator's metric
// scale (eye centres `interpupillary_distance_m` apart).
std::vector<Eigen::Vector3d> head_vertices_m(const Candide3Model& candide, const TexturedHead& head);

class TexturedHeadRenderer {
 public:
  TexturedHeadRenderer(const Candide3Model& candide, TexturedHead head, const PinholeCamera& camera);

  // Draws the head at T_cam_face (face frame as in face_landmark_model.hpp, metres) over `image`
  // (8-bit grey, the camera's size), through the camera's distortion.
  void render(const Eigen::Isometry3d& T_cam_face, cv::Mat& image);
  const TexturedHead& head() const { return head_; }
  // Face-frame vertices in metres (the shape and scale the head is drawn with).
  const std::vector<Eigen::Vector3d>& vertices_m() const { return vertices_m_; }

 private:
  std::vector<std::array<int, 3>> triangles_;
  TexturedHead head_;
  PinholeCamera camera_;
  std::vector<Eigen::Vector3d> vertices_m_;
  cv::Mat ideal_, map_x_, map_y_, warped_, mask_;
};

}  // namespace labo::face
