#pragma once
// Face alignment by a cascade of regression-tree ensembles (Kazemi & Sullivan 2014, "One millisecond
// face alignment with an ensemble of regression trees"), evaluated from a trained model in dlib's
// shape-predictor file format (e.g. the 68-point iBUG model of package libdlib-data).
//
// Each cascade level reads the grey values of a few hundred feature pixels, each placed relative to
// an anchor landmark of the current shape (its offset turned and scaled with the similarity that maps
// the mean shape onto the current one), walks every tree of the level by the differences of two of
// those values against the split's threshold, and adds the leaves' shape increments. Shapes live in
// the face box's normalised frame ((0, 0) its top-left corner, (1, 1) its bottom-right one).
//
// Everything the evaluation needs is laid out flat at load (trees' splits and leaves, the pixels'
// anchors and offsets) and the per-call buffers are sized there too, so fitting allocates nothing.
// The arithmetic is dlib's shape_predictor's (the same float and double steps, landmarks rounded
// to whole pixels), so the landmarks are dlib's: tests/localization/face/landmark_cascade_test.cpp.
#include <Eigen/Core>
#include <cstdint>
#include <filesystem>
#include <opencv2/core.hpp>
#include <vector>

namespace labo::face {

// A face box with inclusive integer corners, as dlib's rectangle (its width in the normalised frame
// is right - left).
struct PixelBox {
  long left = 0, top = 0, right = 0, bottom = 0;
};

class LandmarkCascade {
 public:
  // Throws std::runtime_error naming the file and what is wrong: unreadable, not version 1 of the
  // format, cut short or corrupt in a named part, or inconsistent (a tree that is not complete, leaf
  // increments of another size than the shape, a split or anchor index out of range).
  explicit LandmarkCascade(const std::filesystem::path& model_file);

  int landmark_count() const { return static_cast<int>(mean_shape_.size() / 2); }
  int level_count() const { return static_cast<int>(levels_.size()); }
  std::size_t tree_count() const;
  // Landmark i of the mean shape, in the normalised box frame: where the predictor starts it.
  Eigen::Vector2d mean_landmark(int i) const { return {mean_shape_[2 * i], mean_shape_[2 * i + 1]}; }

  // The landmarks (2 x landmark_count(), whole pixels of `gray`) of the face in `box`. Feature pixels
  // outside the image read 0. `landmarks` is resized only when its size differs. Allocates nothing
  // otherwise.
  void fit(const cv::Mat& gray, const PixelBox& box, Eigen::Matrix2Xd& landmarks);

 private:
  struct Split {
    std::uint32_t first, second;  // feature pixels whose values' difference is tested
    float threshold;              // > threshold: the left child (2 i + 1), else the right (2 i + 2)
  };
  struct Tree {
    std::uint32_t first_split, split_count;  // into Level::splits; a complete tree of split_count + 1 leaves
    std::uint32_t first_leaf;                // into Level::leaves, in units of one shape increment
  };
  struct Level {
    std::vector<std::uint32_t> anchors;  // per feature pixel, its landmark
    std::vector<float> offsets;          // per feature pixel, (dx, dy) from its anchor in the mean shape
    std::vector<Tree> trees;
    std::vector<Split> splits;
    std::vector<float> leaves;           // shape increments, 2 x landmark_count() floats each
  };

  // The linear part (row-major 2 x 2) of the least-squares similarity taking the mean shape onto
  // `shape_`, rounded to float.
  void similarity_from_mean(float m[4]) const;

  std::vector<float> mean_shape_;  // (x0, y0, x1, y1, ...), normalised box frame
  std::vector<Level> levels_;
  double mean_centroid_x_ = 0, mean_centroid_y_ = 0, mean_spread_ = 0;  // of the mean shape
  // Per-call buffers, sized at load.
  std::vector<float> shape_;
  std::vector<float> pixel_values_;
};

}  // namespace labo::face
