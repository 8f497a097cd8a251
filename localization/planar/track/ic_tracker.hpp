#pragma once
// LaboDrone's own homography tracker: pyramidal inverse-compositional Gauss-Newton (Baker & Matthews
// 2004) with the appearance "projected out", so a gain and a bias between template and frame
// (brightness, contrast, auto-exposure) do not disturb it.
//
// Parameterisation: the warp maps normalized template coordinates (centred, half the longer side
// = 1, which keeps the 8x8 Hessian well conditioned) to image pixels; the increment is
// A(p) = [[1+p0, p2, p4], [p1, 1+p3, p5], [p6, p7, 1]] composed inversely, W <- W * A(dp)^-1.
// Everything per template is precomputed at construction: for each template pyramid level a set of
// samples (the strongest gradients of each cell of a grid, so the whole panel constrains the
// perspective terms), their steepest-descent rows orthogonalised against the constant and the
// template itself (bias and gain), and the inverse Hessian. The template level used follows the
// object's apparent size; the frame pyramid is built into reused buffers: no allocation per frame.
//
// IC's fixed point uses the template's gradients only, so when the frame differs from the template
// by more than gain and bias (motion blur, defocus) it is biased. The finest level therefore ends
// with a few ESM iterations (Benhimane & Malis 2004: Jacobian from the mean of the template's and the
// warped frame's gradients, whose fixed point is the true least-squares alignment); they cost one
// 8x8 normal-equation build per iteration (`esm_iterations`, 0 disables).
#include <array>
#include <vector>

#include <Eigen/Core>

#include "localization/planar/track/homography_tracker.hpp"

namespace labo::planar {

class InverseCompositionalTracker final : public HomographyTracker {
 public:
  InverseCompositionalTracker(const cv::Mat& template_gray, const PlanarConfig& config);
  HomographyTrackOutcome track(const cv::Mat& image, const cv::Matx33d& H_prior) override;
  TrackerKind kind() const override { return TrackerKind::InverseCompositional; }

  int template_levels() const { return static_cast<int>(levels_.size()); }

 private:
  struct Sample {
    float xn, yn;   // normalized template coordinates
    float t;        // template value, zero mean and unit RMS over the level's samples
    float gx, gy;   // gradient of that normalized template per normalized unit
    std::array<float, 8> sd;  // steepest-descent row, bias and gain projected out
  };
  struct Level {
    std::vector<Sample> samples;
    // A regular grid over the whole panel for the reported correlation: the high-gradient samples
    // above are the first to suffer from blur, and would understate the match.
    std::vector<Sample> grid;
    Eigen::Matrix<double, 8, 8> hessian;
    Eigen::Matrix<double, 8, 8> hessian_inverse;
  };
  struct Sums;
  struct EsmStep {
    bool ok = false;
    Eigen::Matrix<double, 8, 1> dp;
    double gain = 1;
  };

  void build_level(const cv::Mat& gray, int level);
  // Samples the frame at image level `image_level` through warp P (normalized -> level px).
  Sums accumulate(const std::vector<Sample>& samples, const cv::Mat& image, const cv::Matx33d& P,
                  bool need_hessian) const;

  // A few ESM iterations on the finest level, kept when they raise the correlation.
  void polish_with_esm(const Level& level, const cv::Mat& image, int base, cv::Matx33d& M, int& iterations) const;
  // One ESM step (Benhimane & Malis: the mean of template and frame gradients) at level 0.
  EsmStep esm_step(const std::vector<Sample>& samples, const cv::Mat& image, const cv::Matx33d& M, double gain,
                   double h) const;

  std::vector<Level> levels_;
  cv::Size template_size_;
  cv::Matx33d normalized_from_template_;  // working template px -> normalized
  std::vector<cv::Mat> frame_pyramid_;    // reused buffers, [0] unused (the frame itself)
  std::vector<int> pyramid_scratch_;      // pyr_down_8u's column sums
  PlanarConfig config_;
};

}  // namespace labo::planar
