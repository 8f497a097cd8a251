#pragma once
// Far detection (the paper's Fig. 3): normalized correlation of the template over a pyramid of the
// image, for object widths from a minimum to a maximum in geometric steps. Two searches
// (PlanarConfig::template_search):
//  - coarse_to_fine (the default): the template is resized once, at construction, for every width
//    of the camera's whole range, to the frame pyramid level (cv::pyrDown's) where it is about
//    `detection_coarse_width_px` wide, and one level finer. Per frame: the pyramid, every width in the
//    window matched over its coarse level (zncc_matcher.hpp), the `detection_candidates` best places
//    matched again on the finer level at that width and its two neighbours, in a window of a few
//    pixels. No allocation once the first frame of the camera's size has been seen (the constructor
//    sizes the buffers for it).
//  - per_scale: the search as first built: for each width the whole image area-resized to where the
//    template is `detection_match_width_px` wide, cv::matchTemplate over all of it (several ms a
//    width; the resized templates are made on first use).
// Both return the best place as a homography (working template px -> image px) with its score; found
// when the score exceeds alpha. The tracker refines it.
#include <array>
#include <map>
#include <vector>

#include <opencv2/core.hpp>

#include "localization/planar/detect/planar_detectors.hpp"
#include "localization/planar/detect/zncc_matcher.hpp"
#include "localization/planar/planar_config.hpp"

namespace labo::planar {

class TemplateMatchDetector {
 public:
  // `image_size`: the frames' size (the camera's); the precomputed widths span the configured
  // fractions of its width.
  TemplateMatchDetector(const cv::Mat& working_template, cv::Size image_size, const PlanarConfig& config,
                        double min_correlation);
  // Searches object widths in [min_width_px, max_width_px] (image px). `image` is CV_8UC1.
  Detection detect(const cv::Mat& image, double min_width_px, double max_width_px);

 private:
  // One width of the precomputed range: the template at its coarse and fine pyramid levels.
  struct Scale {
    double width_px = 0;
    int coarse_level = 0, fine_level = 0;
    ZnccTemplate coarse, fine;
    cv::Size coarse_size, fine_size;
  };
  struct Candidate {
    double score = -1;
    int scale = -1;
    cv::Point2d centre;  // level-0 px
  };
  static constexpr int kMaxCandidates = 8;

  Scale make_scale(double width_px, int levels_available) const;
  Detection detect_coarse_to_fine(const cv::Mat& image, double min_width_px, double max_width_px);
  Detection detect_per_scale(const cv::Mat& image, double min_width_px, double max_width_px);
  // The level's prepared image (pyramid built and prepared on demand, once per frame).
  const ZnccImage& level(int index);
  void keep_candidate(const Candidate& c);
  // Working template px -> level-0 px for `size` placed with its top-left pixel at `at` on `level`.
  cv::Matx33d homography(cv::Size size, cv::Point at, int level) const;

  cv::Mat template_;
  PlanarConfig config_;
  double min_correlation_;
  cv::Size image_size_;

  std::vector<Scale> scales_;
  std::vector<cv::Mat> pyramid_;          // [0]: a header over the frame
  std::vector<ZnccImage> prepared_;       // per level
  std::vector<bool> prepared_valid_;      // for the current frame
  std::vector<int> pyramid_scratch_;
  std::vector<float> row_;
  std::array<Candidate, kMaxCandidates> candidates_{};
  int candidate_count_ = 0;

  // per_scale
  const cv::Mat& template_at_width(int width_px);
  std::map<int, cv::Mat> resized_templates_;  // by width, filled on first use
  cv::Mat resized_image_, result_;
};

}  // namespace labo::planar
