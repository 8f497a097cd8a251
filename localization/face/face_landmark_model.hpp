#pragma once
// The rigid part of a person's face as the pose solver sees it: for each used iBUG-68 landmark, a
// 3-D point that is linear in the CANDIDE-3 shape parameters, p_i(τs) = G_i + S_i·τs (model units),
// then scaled to metres so that the interpupillary distance matches the person's measured one.
//
// Face frame (CANDIDE-3's own axes): +x the subject's left (image right when facing the camera), +y
// up, +z out of the face; metres. A face looking straight into an OpenCV camera therefore has
// R_cam_face = diag(1, -1, -1).
#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/candide3.hpp"

namespace labo::face {

// dlib/iBUG-68 landmark indices of the rigid subset: brows, nose, eyes, outer lips (17-59); jaw
// contour (0-16) and inner lips (60-67) move with speech and expression and are left out.
std::vector<int> rigid_landmark_ids();

class FaceLandmarkModel {
 public:
  // `landmark_ids[i]` is the iBUG index of column i; `mean_units` (3 x n) are the neutral points,
  // `shape_basis` (3n x m) stacks each unit's displacement of the n points (x, y, z per point).
  // Throws std::invalid_argument when sizes disagree or both eyes' six landmarks are not present.
  FaceLandmarkModel(std::vector<int> landmark_ids, Eigen::Matrix3Xd mean_units, Eigen::MatrixXd shape_basis,
                    std::vector<std::string> shape_unit_names);

  int size() const { return static_cast<int>(landmark_ids_.size()); }
  int shape_unit_count() const { return static_cast<int>(shape_basis_.cols()); }
  const std::vector<int>& landmark_ids() const { return landmark_ids_; }
  const std::vector<std::string>& shape_unit_names() const { return shape_unit_names_; }
  const Eigen::MatrixXd& shape_basis() const { return shape_basis_; }
  // Column of landmark `id`, -1 when not in the model.
  int column_of(int id) const;

  // Points in model units for shape parameters `tau` (size shape_unit_count()).
  Eigen::Matrix3Xd points_units(const Eigen::VectorXd& tau) const;
  // Distance between the two eye centres (mean of each eye's six landmarks), model units.
  double interpupillary_units(const Eigen::VectorXd& tau) const;
  // Metres per model unit that give `ipd_m` between the eye centres.
  double metres_per_unit(const Eigen::VectorXd& tau, double ipd_m) const;
  // Points in metres (face frame).
  Eigen::Matrix3Xd points_m(const Eigen::VectorXd& tau, double ipd_m) const;

  // Shape units that move at least `min_points` landmarks in the image plane (x or y) by more than
  // `min_motion` units per unit of τs: only those can be fitted from a frontal picture.
  std::vector<bool> observable_units(int min_points = 3, double min_motion = 1e-3) const;

 private:
  std::vector<int> landmark_ids_;
  Eigen::Matrix3Xd mean_units_;
  Eigen::MatrixXd shape_basis_;
  std::vector<std::string> shape_unit_names_;
  std::vector<int> left_eye_cols_, right_eye_cols_;
};

// The landmark model of `landmark_ids` from CANDIDE-3 and the iBUG-68 mapping (interpolated
// landmarks are the weighted sums of their vertices, in the mean and in every shape unit). Throws
// std::invalid_argument when an id is outside 0-67 or has no model point.
FaceLandmarkModel make_face_landmark_model(const Candide3Model& model, const Ibug68Mapping& mapping,
                                           const std::vector<int>& landmark_ids = rigid_landmark_ids());

}  // namespace labo::face
