#pragma once
// Fits a person's CANDIDE-3 shape parameters τs to the landmarks of one frontal picture: regularised
// least squares on τs alternating with the pose (face.md §4, method 1, under full perspective). The
// metric scale comes from the person's interpupillary distance, so τs and the pose are in metres.
#include <Eigen/Geometry>
#include <vector>

#include "localization/face/face_landmark_model.hpp"
#include "localization/face/pnp_solvers.hpp"

namespace labo::face {

struct ShapeFitOptions {
  int alternations = 8;           // pose step + shape step
  int gauss_newton_steps = 3;     // per shape step (the projection is non-linear in τs)
  double landmark_sigma_px = 1.7; // landmark noise, ≈ √3 px
  double regularisation = 1.0;    // λ of the ridge prior ‖τs‖² (units of τs)
  double bound = 1.0;             // |τs| clamp
};

struct ShapeFit {
  Eigen::VectorXd shape_params;   // all units; the unobservable ones stay 0
  std::vector<bool> fitted_units; // which units were estimated
  Eigen::Isometry3d T_cam_face = Eigen::Isometry3d::Identity();
  double rms_px = 0;              // reprojection error with the fitted shape
  double rms_px_mean_shape = 0;   // the same with τs = 0, for comparison
};

// `pixels` (2 x model.size()) are undistorted landmark pixels in the model's column order.
// Throws std::invalid_argument for a size mismatch or a non-positive interpupillary distance, and
// std::runtime_error when no pose in front of the camera fits the landmarks.
ShapeFit fit_shape(const FaceLandmarkModel& model, const Eigen::Matrix2Xd& pixels, const IdealPinhole& camera,
                   double interpupillary_distance_m, const ShapeFitOptions& options = {});

}  // namespace labo::face
