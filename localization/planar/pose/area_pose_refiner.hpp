#pragma once
// Photometric refinement of a planar object's pose in the image domain, each frame pixel predicted as
// a camera forms it: the template's mean over the pixel's footprint on the panel.
//
// Why (docs/planar.md, "the pixel's footprint"): at range (the lab's 0.40 m oscilloscope ~90 px wide
// at 2.5 m) a frame pixel covers several template pixels, and what it records is their area average
// at its own sub-pixel phase, aliasing included. Se3PoseRefiner compares the undistorted frame,
// interpolated at the template samples' positions, with a pyramid level: the level's blur and pixel
// grid are not the frame's, the Laplacian term fixes the blur only to first order and on average, and
// the remaining phase-dependent difference (2.7-4.8 grey levels RMS on noise-free, area-correct
// renders) bends the fitted shape, which face-on at 2-3 m is a tilt of a degree. Here the prediction
// of pixel p is the box integral of the template (a summed-area table of the original image, exact for
// its piecewise-constant texels) over p's footprint: the pixel square mapped through the lens and the
// current pose, as a box with its second moments along the template's axes. The residual is read at
// the raw frame's integer pixels: the frame is neither undistorted (the remap's bilinear resampling
// mixed neighbouring pixels at a phase that varies over the panel) nor smoothed nor interpolated.
//
// Model: I(p) = a(X) (P(p; T) + beta Q(p; T)) + b, with the gain a affine across the panel, bias b,
// and beta the frame's blur beyond the pixel's box (a lens, a Bayer filter), in raw px^2: Q is the
// prediction's change per px^2 of footprint variance (the footprint widened by kWiden). Gauss-Newton
// on T <- exp(xi) T and the 5 appearance parameters; the Jacobian of the prediction's motion uses the
// frame's gradient at the pixel (a times the prediction's at the fit). Pixels: the strongest frame
// gradients of each cell of a 6 x 6 grid over the panel, at most Se3RefinerSettings::max_samples,
// chosen once per frame by select(). No motion-blur model (the localizer uses Se3PoseRefiner when it
// models one). Allocates nothing per call once its buffers have grown.
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "core/camera_model.hpp"
#include "localization/planar/pose/se3_pose_refiner.hpp"

namespace labo::planar {

class AreaPoseRefiner {
 public:
  // `template_image`: CV_8UC1 at any resolution (the original photo is best: the box integral is exact
  // for its texels); pixel (u, v) lies at (((u + 0.5) / w - 0.5) * width_m, ((v + 0.5) / h - 0.5) *
  // height_m, 0). `camera`: the raw frames' model, distortion included.
  AreaPoseRefiner(const cv::Mat& template_image, double width_m, double height_m, const PinholeCamera& camera,
                  const Se3RefinerSettings& settings = {});

  // Chooses the pixels to fit in `raw` (the camera's frame as it came: CV_8UC1, the camera's size,
  // distorted) around pose T (camera from object): the strongest gradients of each cell, read once
  // per frame for all the refinements of that frame (IPPE's branches, the mirrored pose). False when
  // the frame is not the camera's or too little of the panel is in view.
  bool select(const cv::Mat& raw, const Eigen::Isometry3d& T) const;
  // Refines T_start (e.g. the IPPE pose in the undistorted frame, same K) on the pixels of the last
  // select(). The corner leash (undistorted px) and the covariance as Se3PoseRefiner's.
  Se3Refinement refine(const Eigen::Isometry3d& T_start, const Eigen::Isometry3d* warm_start = nullptr) const;
  // select() then refine(): for one-off calls.
  Se3Refinement refine(const cv::Mat& raw, const Eigen::Isometry3d& T_start) const;
  int selected_pixels() const { return static_cast<int>(samples_.size()); }

 private:
  struct Sample {
    int x, y;               // raw pixel
    float grey;             // its value
    Eigen::Vector2f pu;     // undistorted position
    Eigen::Matrix2f D;      // d(undistorted) / d(raw) at the pixel
    Eigen::Vector2f gradient;  // the frame's grey-level gradient at the pixel, per undistorted px
    float hx, hy;           // the footprint's half-sizes (template px) at the pose of select(): within
                            // a refinement's reach (a corner moves <= 1.5 px) they change by < 1 %
  };
  // The appearance's blur is in raw px^2 (see the header comment).
  PhotometricNormal accumulate(const Eigen::Isometry3d& T, const PanelAppearance& a) const;
  // Mean of the template over [x0, x1] x [y0, y1] (template px, texel edges at integers).
  double box_mean(double x0, double y0, double x1, double y1) const;
  Eigen::Vector2f undistorted_at(int x, int y) const;

  cv::Mat sat_;  // CV_64FC1, (h + 1) x (w + 1): sums of the template over [0, x) x [0, y)
  int tw_ = 0, th_ = 0;
  double width_m_, height_m_;
  PinholeCamera camera_;
  double fx_, fy_, cx_, cy_;
  Se3RefinerSettings settings_;
  cv::Mat undistorted_of_raw_;  // CV_32FC2: each raw pixel's undistorted position (empty: no distortion)
  struct Candidate {
    int x, y, cell;
    float strength;
  };
  mutable std::vector<Sample> samples_;
  mutable std::vector<Candidate> candidates_, by_cell_;
  mutable std::vector<float> cell_strengths_;
};

}  // namespace labo::planar
