#pragma once
// Photometric refinement of a planar object's pose directly in SE(3) (6 DoF), after the 8-DoF
// homography tracker and IPPE.
//
// Why: with K and the panel's metric size known, a plane's image is H = K [r1 r2 t] S, 6 parameters.
// The tracker estimates 8; the 2 extra ones (aspect ratio and shear) are not constrained by the
// physics, and IPPE turns their small errors into large tilts when the panel is seen nearly
// face-on: the aspect ratio changes with the tilt only as cos(tilt) = 1 - tilt^2 / 2, so an aspect
// error e reads as a tilt of sqrt(2 e). At 2.5 m (a 0.40 m panel ~90 px wide) 0.01 px on one corner
// moves the IPPE rotation by ~0.25 deg face-on (~0.04 deg at 7 deg obliquity). Aligning the template
// under the plane-induced warp u = pi(K (R X + t)) itself, with all the panel's pixels, fixes the tilt
// from the perspective terms to first order, and the rotation error becomes linear in the image noise.
//
// Method: Gauss-Newton on the template's high-gradient samples of the pyramid level matching the
// panel's apparent size (as the tracker), in the undistorted frame at full resolution: residual
// I(u(X; T)) - a(X) t(X) - b with a gain a(X) (affine across the panel: a light gradient) and a bias b
// estimated jointly (brightness, contrast), the
// Jacobian from the frame's gradients at the warped points (so the fixed point is the least-squares
// pose even when the frame is blurrier than the template), increment T <- exp(xi) T (camera frame).
// The covariance of the 6 pose parameters is the Gauss-Newton one, sigma^2 (J^T J)^-1, with sigma^2
// the residual variance, inflated by `covariance_inflation` (neighbouring pixels' errors are
// correlated: blur, interpolation, compression), plus a floor on the rotation for the model errors
// it cannot see. On the SmoothedFrame path LaboDrone allocates nothing per call once the buffers
// have the frame's size (OpenCV's Gaussian filter keeps its own small row buffers).
//
// Blur: a Laplacian term in the appearance model absorbs the remaining difference between the
// frame's blur and the level's (Se3RefinerSettings::estimate_blur).
//
// Smoothing: the frame and the template are resampled differently (the camera or renderer integrates
// over pixels and mip levels, the template pyramid is cv::pyrDown's 5-tap Gaussian), and at 2-3 m, where
// 0.01 px on a corner is 0.25 deg of tilt, that mismatch dominates the error, with or without sensor
// noise and motion blur (degrees on the simulated lab's 0.40 x 0.20 m oscilloscope). Smoothing both
// with the same small Gaussian (`smoothing_sigma_px`, in frame pixels; the template level matches the
// panel's apparent size, so in level pixels too) makes the two agree (docs/planar.md).
#include <initializer_list>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "localization/planar/image_ops.hpp"

namespace labo::planar {

struct PhotometricNormal;
struct PanelAppearance;

struct Se3RefinerSettings {
  int max_iterations = 8;
  int max_samples = 1500;              // per template level
  double convergence_px = 0.002;       // stop when no panel corner moves more than this
  double max_corner_shift_px = 1.5;    // refused when a corner moves farther from the starting pose
  // The camera's calibration error at the image's corner (CameraIntrinsics::calibration_error_px): the
  // leash grows by it times the panel's farthest point's distance from the principal point over the
  // half diagonal. The homography bends with the lens the configured model lacks; the rigid plane
  // cannot, so the two fits of one frame part by about that much.
  double calibration_error_px = 0.0;
  double covariance_inflation = 3.0;   // on the Gauss-Newton standard deviations
  double rotation_sigma_floor_rad = 0.0026;  // 0.15 deg, added in quadrature (model errors)
  double smoothing_sigma_px = 0.5;     // Gaussian on frame and template before the fit; 0 = none
  // true: at range the template is area-resampled to 1.3x the panel's apparent size and blurred like
  // the frame (se3_pose_refiner.cpp, kOversampling); false: always the pyramid level matching the
  // apparent size (the tracker's rule). Config: planar.se3_template_resolution "frame" | "pyramid".
  // Not the default: with the blur fixed it is better on the simulated lab's renderer and worse on this
  // module's; with the blur estimated (estimate_blur) it is worse on both (docs/planar.md).
  bool resample_to_frame = false;
  // true: the fit also estimates how much blurrier (or sharper) the frame is than the template level,
  // as a multiple of the level's Laplacian (template * Gaussian of variance v = template + v/2 Laplacian
  // to first order), one more linear parameter beside gain and bias. Why: the camera's (or renderer's)
  // blur differs from the level's and changes with the range (the level is up to 0.3 octave coarser or
  // 0.7 finer than the panel's image); with the blur fixed the fit bends the panel's shape to absorb
  // the difference, and face-on at 2-3 m a shape change is a tilt of degrees. Config:
  // planar.se3_estimate_blur (default true; docs/planar.md, "the frame's blur estimated").
  bool estimate_blur = true;
  // A refinement whose model correlates with the frame's grey levels below this is refused
  // (Se3Refinement::contradicts_start): the localizer passes the detection threshold alpha. 0: off.
  double min_correlation = 0.0;
};

struct Se3Refinement {
  bool refined = false;  // false: keep the starting pose (`failure` says why)
  Eigen::Isometry3d T_cam_object = Eigen::Isometry3d::Identity();
  // Covariance of (rotation vector rad, translation m) of a left perturbation exp(xi) T (camera frame).
  Eigen::Matrix<double, 6, 6> covariance = Eigen::Matrix<double, 6, 6>::Zero();
  double rotation_sigma_rad = 0;  // 1-sigma along the worst-determined rotation axis
  double position_sigma_m = 0;    // 1-sigma along the worst-determined direction of T_cam_object's translation
  double residual_grey = 0;       // RMS residual after gain and bias
  double blur_variance_px2 = 0;   // estimate_blur: the frame's extra blur, Gaussian variance in frame px^2
  double correlation = 0;         // of the fitted model with the frame's grey levels (sqrt of the variance explained)
  int iterations = 0;
  const char* failure = "";
  // Not refined because the photometric fit disagrees with the starting pose: it ended beyond the
  // corner leash, or the panel's appearance could not be fitted at all (the gain collapsed). The
  // starting pose (the tracker's homography through IPPE) is then suspect, unlike a refusal for too
  // few pixels in view or a template too small to refine.
  bool contradicts_start = false;
};

class Se3PoseRefiner {
 public:
  // `working_template` (CV_8UC1) is the template the tracker uses; its pixel (u, v) lies at the object
  // point (((u + 0.5) / w - 0.5) * width_m, ((v + 0.5) / h - 0.5) * height_m, 0). K has no distortion
  // (the frames are undistorted).
  Se3PoseRefiner(const cv::Mat& working_template, double width_m, double height_m, const cv::Matx33d& K,
                 const Se3RefinerSettings& settings = {});

  // The frame as the refinement reads it: smoothed like the template where the panel is.
  struct SmoothedFrame {
    cv::Mat image;    // CV_8UC1, frame size; only `valid` is meaningful
    cv::Rect valid;   // the region smoothed (the whole frame when smoothing is off)
    mutable std::vector<float> blurred_template;  // scratch: the template samples blurred like the frame
    mutable std::vector<float> blurred_laplacian;  // scratch: their Laplacians blurred the same way
    std::vector<float> blur_rows;  // scratch of smooth()'s Gaussian
  };
  // Smooths the region the panel covers at any of `poses` (plus the refinement's reach) into `out`;
  // reuses out's frame-sized buffer. `undistorted` is CV_8UC1.
  void smooth(const cv::Mat& undistorted, std::initializer_list<Eigen::Isometry3d> poses, SmoothedFrame& out) const;
  // `T_start` is the IPPE pose (camera from object); `frame` comes from smooth() with T_start among its poses.
  // `blur_px`: the panel's apparent motion during the exposure (undistorted-frame pixels, at its
  // centre). When it is longer than half a pixel the template is blurred the same way before the fit:
  // a sharp template against a smeared frame pulls the pose by degrees (docs/planar.md).
  // `warm_start` (optional): where the iterations begin, e.g. the refined pose of a neighbouring blur
  // hypothesis (fewer iterations); the corner leash is still measured from T_start.
  Se3Refinement refine(const SmoothedFrame& frame, const Eigen::Isometry3d& T_start,
                       const Eigen::Vector2d& blur_px = Eigen::Vector2d::Zero(),
                       const Eigen::Isometry3d* warm_start = nullptr) const;
  // Convenience for one-off calls (tests, tools): smooths around T_start, then refines. Allocates.
  Se3Refinement refine(const cv::Mat& undistorted, const Eigen::Isometry3d& T_start) const;

  int levels() const { return static_cast<int>(levels_.size()); }
  // The template the last refine() fitted (a pyramid level's size or the resampled one's), and how
  // many times the resampled template was built: for tests.
  cv::Size last_template_size() const { return last_template_size_; }
  int resample_builds() const { return resampled_.builds; }

 private:
  struct Sample {
    float X, Y;    // object frame, metres (Z = 0)
    float t;       // template grey level
    float lx, ly;  // position in its level's image, px
    float laplacian;  // of the (smoothed) level image at the sample, grey levels per px^2
  };

  // A template image the fit reads: its samples, the (smoothed) image they come from, metres per
  // pixel of that image along the panel's x and y.
  struct View {
    const std::vector<Sample>* samples = nullptr;
    const cv::Mat* image = nullptr;
    const cv::Mat* laplacian = nullptr;  // CV_32FC1, of `image`
    double mx = 0, my = 0;
  };
  // The template resampled for the frame, rebuilt when the panel's apparent size changes by more than
  // 2 %; its buffers have the working template's size (allocated once), the images are headers.
  struct Resampled {
    cv::Size size;  // 0 x 0: not built (or too little texture at that size)
    double target_w = 0, target_h = 0;
    std::vector<Sample> samples;
    std::vector<uchar> area, smoothed;
    std::vector<float> gx, gy, magnitude, strengths, laplacian;
    cv::Mat image, laplacian_image;
    int builds = 0;
  };
  void add_level(const cv::Mat& gray, int level);
  // The strongest gradients of each cell of `gray` (smoothed); pixel (x, y) is at object (x mx + bx, y my + by).
  void select_samples(const cv::Mat& gray, const cv::Mat& magnitude, const cv::Mat& laplacian, double mx, double my,
                      double bx, double by, int border, std::vector<float>& strengths, std::vector<Sample>& out) const;
  int level_for(const Eigen::Isometry3d& T) const;
  // The template to fit at pose T: resampled for the frame, or a pyramid level.
  View view_for(const Eigen::Isometry3d& T) const;
  // `values` / `laplacians`: the samples' template grey levels and Laplacians to fit (blurred), or null
  // for their own.
  // The appearance's blur is half the frame's extra blur variance in template-view px^2 (estimate_blur).
  PhotometricNormal accumulate(const std::vector<Sample>& samples, const float* values, const float* laplacians,
                               const SmoothedFrame& frame, const Eigen::Isometry3d& T, const PanelAppearance& appearance) const;
  // The view's samples averaged along the blur (image px mapped into the view at the panel's centre).
  void blur_samples(const View& view, const Eigen::Isometry3d& T, const Eigen::Vector2d& blur_px,
                    std::vector<float>& out, std::vector<float>& out_laplacian) const;

  cv::Mat working_;
  std::vector<std::vector<Sample>> levels_;
  std::vector<cv::Mat> level_images_;  // the levels as sampled (smoothed), for blurring the samples
  std::vector<cv::Mat> level_laplacians_;  // their Laplacians (CV_32FC1)
  mutable Resampled resampled_;
  mutable cv::Size last_template_size_;
  cv::Size template_size_;
  double width_m_, height_m_;
  double fx_, fy_, cx_, cy_;
  Se3RefinerSettings settings_;
  GaussianBlur8u frame_blur_;  // smooth()'s Gaussian (cv::GaussianBlur's pixels, no allocation per call)
};

}  // namespace labo::planar
