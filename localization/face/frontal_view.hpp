#pragma once
// A frontal, upright view of the tracked face for the landmark predictor.
//
// dlib's ERT was trained mostly on near-frontal faces; on a head turned beyond ~20° it pulls the
// landmarks back towards a frontal shape, which biases yaw (and tz with it). Stretching the crop
// across the face (a planar approximation) did not change that bias. This view undoes the last
// frame's head rotation through the person's CANDIDE-3 mesh instead: each work pixel takes the camera
// pixel that the mesh triangle under it shows at the last pose (piecewise affine, distortion
// included), so the predictor sees the face from the front; its landmarks are mapped back through the
// same triangles. The mapping is exact in both directions for whatever the image shows, so an error
// of the last pose only leaves the face less than frontal in the view, it does not move the landmarks.
#include <Eigen/Geometry>
#include <array>
#include <opencv2/core.hpp>
#include <vector>

#include "core/camera_model.hpp"

namespace labo::face {

class FrontalView {
 public:
  explicit FrontalView(std::vector<std::array<int, 3>> triangles);
  // The person's mesh in the face frame, metres (face_landmark_model.hpp's axes).
  void set_vertices(std::vector<Eigen::Vector3d> vertices_m);

  // Builds the view of `gray` (the camera's image) with a virtual camera of focal `focal_px` whose
  // principal point is the view's centre, looking at the face's origin head-on from its distance at
  // T_cam_face (the face upright). `shift_px` moves the mesh in the camera image (the predicted
  // motion since T_cam_face). Returns false, leaving no view, when a vertex is behind the camera.
  bool render(const cv::Mat& gray, const PinholeCamera& camera, const Eigen::Isometry3d& T_cam_face,
              const Eigen::Vector2d& shift_px, double focal_px, cv::Size size);

  const cv::Mat& image() const { return view_; }
  // View pixel of a face-frame point (metres).
  Eigen::Vector2d view_of(const Eigen::Vector3d& p_face) const;
  // Camera image pixel shown at a view pixel: through the mesh triangle under it (within 3 px of
  // the mesh: the nearest one's), or, farther off the mesh, the affine map that best fits all
  // vertices.
  Eigen::Vector2d image_of(const Eigen::Vector2d& view_px) const;

 private:
  void rasterise(cv::Size size);

  std::vector<std::array<int, 3>> triangles_;
  std::vector<Eigen::Vector3d> vertices_m_;
  double focal_px_ = 1, distance_m_ = 1;
  Eigen::Vector2d centre_px_ = Eigen::Vector2d::Zero();
  Eigen::Matrix2Xd view_vertices_, image_vertices_;
  std::vector<Eigen::Matrix<double, 2, 3>> triangle_maps_;  // view pixel (homogeneous) -> image pixel
  Eigen::Matrix<double, 2, 3> fallback_map_ = Eigen::Matrix<double, 2, 3>::Zero();
  cv::Mat triangle_id_, depth_, map_x_, map_y_, view_;  // views of the storages below (face_image_warp.hpp)
  cv::Mat triangle_id_storage_, depth_storage_, map_x_storage_, map_y_storage_, view_storage_;
};

}  // namespace labo::face
