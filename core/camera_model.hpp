#pragma once
// Pinhole camera with Brown-Conrady distortion (k1, k2, p1, p2, k3), OpenCV's convention, so the
// same numbers work in cv::projectPoints, cv::undistort and here.
#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <optional>
#include <string>

namespace labo {

struct CameraIntrinsics {
  int width = 640;
  int height = 360;
  double fx = 0, fy = 0, cx = 0, cy = 0;
  double k1 = 0, k2 = 0, p1 = 0, p2 = 0, k3 = 0;
  // How far this model may put a point at the image's corner from where the lens really images it:
  // a calibration shared by every drone of a model differs from each unit's lens (focal length by a
  // few per cent, distortion), and a camera configured without distortion has some. Checks that
  // compare two fits of the same image widen by it, in proportion to the distance from the centre.
  double calibration_error_px = 0;
};

// Throws std::invalid_argument naming the bad field (non-positive size or focal length, principal
// point outside the image, non-finite value).
void validate(const CameraIntrinsics& intrinsics, const std::string& name);

class PinholeCamera {
 public:
  explicit PinholeCamera(const CameraIntrinsics& intrinsics);

  // AR.Drone 2.0 defaults: front 640x360 with distortion; bottom 640x360, none.
  static PinholeCamera ardrone2_front();
  static PinholeCamera ardrone2_bottom();

  const CameraIntrinsics& intrinsics() const { return k_; }
  int width() const { return k_.width; }
  int height() const { return k_.height; }
  bool has_distortion() const;
  cv::Matx33d K() const;
  cv::Mat distortion_coefficients() const;  // 1x5: k1 k2 p1 p2 k3

  // Normalized image coordinates (x/z, y/z) through distortion.
  Eigen::Vector2d distort(const Eigen::Vector2d& undistorted) const;
  // Inverse of distort, by fixed-point iteration (converges for the AR.Drone's lens).
  Eigen::Vector2d undistort(const Eigen::Vector2d& distorted) const;

  // Pixel of a point in camera coordinates; empty when behind the camera (z <= 1 mm).
  std::optional<Eigen::Vector2d> project(const Eigen::Vector3d& p_cam) const;
  // Unit ray through a pixel, in camera coordinates.
  Eigen::Vector3d unproject(const Eigen::Vector2d& pixel) const;
  bool in_image(const Eigen::Vector2d& pixel, double margin = 0.0) const;

  // The same camera at another resolution (pyramids, downscaled searches).
  PinholeCamera scaled(double factor) const;
  PinholeCamera without_distortion() const;

 private:
  CameraIntrinsics k_;
};

}  // namespace labo
