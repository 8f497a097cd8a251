#include "localization/face/landmark_cascade.hpp"

#include <cmath>
#include <fstream>
#include <limits>
#include <stdexcept>
#include <string>

// Only to read the file: dlib's serialization of its regression trees (dlib::impl::regression_tree,
// dlib::impl::split_feature) and of its matrices and vectors.
#include <dlib/image_processing/shape_predictor.h>

namespace labo::face {

namespace {

constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();

bool is_power_of_two(std::size_t n) { return n > 0 && (n & (n - 1)) == 0; }

// Reads one part of the file with dlib's deserialization, naming the part when it fails.
template <typename T>
void read_part(std::istream& in, T& item, const std::string& file, const char* part) {
  try {
    dlib::deserialize(item, in);
  } catch (const std::exception& e) {
    throw std::runtime_error(file + ": not a usable dlib shape predictor: " + part +
                             " cut short or corrupt (" + e.what() + ")");
  }
}

}  // namespace

LandmarkCascade::LandmarkCascade(const std::filesystem::path& model_file) {
  const std::string file = model_file.string();
  std::ifstream in(model_file, std::ios::binary);
  if (!in) throw std::runtime_error(file + ": cannot open the shape predictor (package libdlib-data)");
  const auto fail = [&file](const std::string& what) {
    return std::runtime_error(file + ": not a usable dlib shape predictor: " + what);
  };

  // The format: a version int (1), the mean shape, the forests (per cascade level, its trees), per
  // level the feature pixels' anchor landmarks, per level their offsets from those anchors.
  int version = 0;
  read_part(in, version, file, "the version number");
  if (version != 1) throw fail("format version " + std::to_string(version) + ", expected 1");
  dlib::matrix<float, 0, 1> mean_shape;
  read_part(in, mean_shape, file, "the mean shape");
  if (mean_shape.size() < 4 || mean_shape.size() % 2 != 0) {
    throw fail("a mean shape of " + std::to_string(mean_shape.size()) + " values (expected 2 per landmark, 2 landmarks or more)");
  }
  mean_shape_.assign(mean_shape.begin(), mean_shape.end());
  const std::size_t shape_size = mean_shape_.size();
  const auto landmarks = static_cast<std::uint32_t>(shape_size / 2);

  std::vector<std::vector<dlib::impl::regression_tree>> forests;
  read_part(in, forests, file, "the regression forests");
  std::vector<std::vector<unsigned long>> anchors;
  read_part(in, anchors, file, "the feature pixels' anchor landmarks");
  std::vector<std::vector<dlib::vector<float, 2>>> offsets;
  read_part(in, offsets, file, "the feature pixels' offsets");
  if (forests.empty()) throw fail("no cascade level");
  if (anchors.size() != forests.size() || offsets.size() != forests.size()) {
    throw fail(std::to_string(forests.size()) + " cascade levels of trees but " + std::to_string(anchors.size()) +
               " of anchor landmarks and " + std::to_string(offsets.size()) + " of offsets");
  }

  std::size_t max_pixels = 0;
  levels_.resize(forests.size());
  for (std::size_t l = 0; l < forests.size(); ++l) {
    const std::string where = "cascade level " + std::to_string(l);
    Level& level = levels_[l];
    const std::size_t pixels = anchors[l].size();
    if (offsets[l].size() != pixels) {
      throw fail(where + " has " + std::to_string(pixels) + " anchor landmarks but " + std::to_string(offsets[l].size()) +
                 " offsets");
    }
    if (pixels == 0 || pixels >= kNone) throw fail(where + " has " + std::to_string(pixels) + " feature pixels");
    max_pixels = std::max(max_pixels, pixels);
    level.anchors.resize(pixels);
    level.offsets.resize(2 * pixels);
    for (std::size_t i = 0; i < pixels; ++i) {
      if (anchors[l][i] >= landmarks) {
        throw fail(where + ": feature pixel " + std::to_string(i) + " is anchored to landmark " + std::to_string(anchors[l][i]) +
                   " of " + std::to_string(landmarks));
      }
      level.anchors[i] = static_cast<std::uint32_t>(anchors[l][i]);
      level.offsets[2 * i] = offsets[l][i].x();
      level.offsets[2 * i + 1] = offsets[l][i].y();
    }

    std::size_t split_total = 0, leaf_total = 0;
    for (const auto& tree : forests[l]) {
      split_total += tree.splits.size();
      leaf_total += tree.leaf_values.size();
    }
    if (forests[l].empty()) throw fail(where + " has no tree");
    if (split_total >= kNone || leaf_total >= kNone) throw fail(where + " is too large");
    level.trees.reserve(forests[l].size());
    level.splits.reserve(split_total);
    level.leaves.reserve(leaf_total * shape_size);
    for (std::size_t t = 0; t < forests[l].size(); ++t) {
      const auto& tree = forests[l][t];
      const std::string tree_name = where + ", tree " + std::to_string(t);
      if (!is_power_of_two(tree.leaf_values.size()) || tree.leaf_values.size() != tree.splits.size() + 1) {
        throw fail(tree_name + " has " + std::to_string(tree.splits.size()) + " splits and " +
                   std::to_string(tree.leaf_values.size()) + " leaves (a complete tree: a power of 2 leaves, one more than its splits)");
      }
      level.trees.push_back({static_cast<std::uint32_t>(level.splits.size()), static_cast<std::uint32_t>(tree.splits.size()),
                             static_cast<std::uint32_t>(level.leaves.size() / shape_size)});
      for (const auto& s : tree.splits) {
        if (s.idx1 >= pixels || s.idx2 >= pixels) {
          throw fail(tree_name + " compares feature pixels " + std::to_string(s.idx1) + " and " + std::to_string(s.idx2) +
                     ", the level has " + std::to_string(pixels));
        }
        level.splits.push_back({static_cast<std::uint32_t>(s.idx1), static_cast<std::uint32_t>(s.idx2), s.thresh});
      }
      for (const auto& leaf : tree.leaf_values) {
        if (static_cast<std::size_t>(leaf.size()) != shape_size) {
          throw fail(tree_name + " has a leaf of " + std::to_string(leaf.size()) + " values, the shape " +
                     std::to_string(shape_size));
        }
        level.leaves.insert(level.leaves.end(), leaf.begin(), leaf.end());
      }
    }
    // The level is copied: free dlib's copy now (the 68-point model's leaves are ~65 MB).
    std::vector<dlib::impl::regression_tree>().swap(forests[l]);
  }

  // The mean shape's centroid and spread, as every level's similarity needs them.
  for (std::uint32_t i = 0; i < landmarks; ++i) {
    mean_centroid_x_ += mean_shape_[2 * i];
    mean_centroid_y_ += mean_shape_[2 * i + 1];
  }
  mean_centroid_x_ /= landmarks;
  mean_centroid_y_ /= landmarks;
  for (std::uint32_t i = 0; i < landmarks; ++i) {
    const double dx = mean_shape_[2 * i] - mean_centroid_x_, dy = mean_shape_[2 * i + 1] - mean_centroid_y_;
    mean_spread_ += dx * dx + dy * dy;
  }
  mean_spread_ /= landmarks;
  if (!(mean_spread_ > 0)) throw fail("a mean shape whose landmarks all coincide");

  shape_.resize(shape_size);
  pixel_values_.resize(max_pixels);
}

std::size_t LandmarkCascade::tree_count() const {
  std::size_t n = 0;
  for (const auto& level : levels_) n += level.trees.size();
  return n;
}

void LandmarkCascade::similarity_from_mean(float m[4]) const {
  // Least squares over the landmarks (Umeyama 1991): with C the cross-covariance of the centred
  // current shape against the centred mean shape and s² the mean shape's spread, the best rotation
  // in the plane is at angle atan2(C10 - C01, C00 + C11) and the scale is the length of that vector
  // over s², so scale x rotation = [a -b; b a] / s² with a = C00 + C11, b = C10 - C01. Sums in
  // double, in landmark order; rounded to float at the end, as the pixel placement is in float.
  const std::size_t n = shape_.size() / 2;
  double cx = 0, cy = 0;
  for (std::size_t i = 0; i < n; ++i) {
    cx += shape_[2 * i];
    cy += shape_[2 * i + 1];
  }
  cx /= static_cast<double>(n);
  cy /= static_cast<double>(n);
  double c00 = 0, c01 = 0, c10 = 0, c11 = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double tx = shape_[2 * i] - cx, ty = shape_[2 * i + 1] - cy;
    const double fx = mean_shape_[2 * i] - mean_centroid_x_, fy = mean_shape_[2 * i + 1] - mean_centroid_y_;
    c00 += tx * fx;
    c01 += tx * fy;
    c10 += ty * fx;
    c11 += ty * fy;
  }
  const double nd = static_cast<double>(n);
  const double a = (c00 / nd + c11 / nd) / mean_spread_;
  const double b = (c10 / nd - c01 / nd) / mean_spread_;
  m[0] = static_cast<float>(a);
  m[1] = static_cast<float>(-b);
  m[2] = static_cast<float>(b);
  m[3] = static_cast<float>(a);
}

void LandmarkCascade::fit(const cv::Mat& gray, const PixelBox& box, Eigen::Matrix2Xd& landmarks) {
  if (gray.empty() || gray.type() != CV_8UC1) throw std::invalid_argument("landmark cascade: expected an 8-bit grey image");
  // The box's frame to pixels: (0, 0) -> its top-left corner, (1, 1) -> its bottom-right one;
  // positions rounded half up to whole pixels.
  const double width = static_cast<double>(box.right - box.left), height = static_cast<double>(box.bottom - box.top);
  const double left = static_cast<double>(box.left), top = static_cast<double>(box.top);
  const double last_col = gray.cols - 1, last_row = gray.rows - 1;

  shape_ = mean_shape_;  // same size: no allocation
  for (const Level& level : levels_) {
    float m[4];
    similarity_from_mean(m);
    const std::size_t pixels = level.anchors.size();
    for (std::size_t i = 0; i < pixels; ++i) {
      const std::uint32_t anchor = level.anchors[i];
      const float dx = level.offsets[2 * i], dy = level.offsets[2 * i + 1];
      // In float, turned offset first and then the anchor added.
      const float turned_x = m[0] * dx + m[1] * dy, turned_y = m[2] * dx + m[3] * dy;
      const float x = turned_x + shape_[2 * anchor], y = turned_y + shape_[2 * anchor + 1];
      const double col = std::floor(width * x + left + 0.5), row = std::floor(height * y + top + 0.5);
      pixel_values_[i] = col >= 0 && col <= last_col && row >= 0 && row <= last_row
                             ? static_cast<float>(gray.ptr<unsigned char>(static_cast<int>(row))[static_cast<int>(col)])
                             : 0.0f;
    }
    const float* values = pixel_values_.data();
    const std::size_t shape_size = shape_.size();
    float* shape = shape_.data();
    for (const Tree& tree : level.trees) {
      const Split* splits = level.splits.data() + tree.first_split;
      std::uint32_t node = 0;
      while (node < tree.split_count) {
        const Split& s = splits[node];
        node = values[s.first] - values[s.second] > s.threshold ? 2 * node + 1 : 2 * node + 2;
      }
      const float* increment = level.leaves.data() + (tree.first_leaf + (node - tree.split_count)) * shape_size;
      for (std::size_t j = 0; j < shape_size; ++j) shape[j] += increment[j];
    }
  }

  const Eigen::Index n = static_cast<Eigen::Index>(shape_.size() / 2);
  if (landmarks.cols() != n) landmarks.resize(2, n);
  for (Eigen::Index i = 0; i < n; ++i) {
    landmarks(0, i) = std::floor(width * shape_[static_cast<std::size_t>(2 * i)] + left + 0.5);
    landmarks(1, i) = std::floor(height * shape_[static_cast<std::size_t>(2 * i + 1)] + top + 0.5);
  }
}

}  // namespace labo::face
