#pragma once
// The template of a planar object (instrument front panel, landing platform): its grey image, its
// physical size, and the object-frame convention of drone/lab/lab_description.hpp: origin at the
// panel's centre, x right, y down (as in the image), z into the panel; template pixel (u, v) lies at
// (((u + 0.5) / w - 0.5) * width_m, ((v + 0.5) / h - 0.5) * height_m, 0).
//
// Large photos are downscaled to a working image for tracking; every homography that leaves this
// module maps *original* template pixels, and `working_from_original()` converts.
#include <array>
#include <filesystem>
#include <string>

#include <opencv2/core.hpp>

#include "localization/planar/planar_config.hpp"

namespace labo::planar {

class PlanarTemplate {
 public:
  // Throws std::invalid_argument naming `name` and the reason: empty image, smaller than 32 px,
  // non-positive or non-finite size, too little texture (which test failed, with the measured value).
  static PlanarTemplate create(const cv::Mat& image, double width_m, double height_m, const std::string& name,
                               const PlanarConfig& config);
  // Reads the image file first; an unreadable or empty file is refused the same way.
  static PlanarTemplate load(const std::filesystem::path& file, double width_m, double height_m,
                             const PlanarConfig& config);

  const std::string& name() const { return name_; }
  const cv::Mat& working() const { return working_; }  // CV_8UC1
  // The image as given, in grey (CV_8UC1): the footprint refinement integrates its texels.
  const cv::Mat& original() const { return original_; }
  cv::Size original_size() const { return original_size_; }
  double width_m() const { return width_m_; }
  double height_m() const { return height_m_; }

  // Maps original template pixels to working pixels (a scale about pixel centres).
  const cv::Matx33d& working_from_original() const { return working_from_original_; }
  // Corners of the panel in working pixels (pixel edges: -0.5 .. w-0.5), clockwise from top-left.
  std::array<cv::Point2d, 4> working_corners() const;
  // The same corners in the object frame, metres.
  std::array<cv::Point3d, 4> object_corners() const;

 private:
  PlanarTemplate() = default;
  std::string name_;
  cv::Mat working_;
  cv::Mat original_;
  cv::Size original_size_;
  double width_m_ = 0, height_m_ = 0;
  cv::Matx33d working_from_original_ = cv::Matx33d::eye();
};

// The texture measures the refusal is based on (exposed for tests and the docs).
struct TextureMeasures {
  double intensity_stddev = 0;
  double edge_fraction = 0;     // pixels whose gradient exceeds 16 grey levels per pixel
  double gradient_isotropy = 0; // smaller / larger eigenvalue of the summed gradient structure tensor
};
TextureMeasures measure_texture(const cv::Mat& gray);

// Projects a point through a homography.
cv::Point2d apply_homography(const cv::Matx33d& H, const cv::Point2d& p);
// Corner RMS (sqrt of the mean squared point distance) between two corner sets.
double corner_rms(const std::array<cv::Point2d, 4>& a, const std::array<cv::Point2d, 4>& b);
// The four points through H.
std::array<cv::Point2d, 4> map_corners(const cv::Matx33d& H, const std::array<cv::Point2d, 4>& corners);

}  // namespace labo::planar
