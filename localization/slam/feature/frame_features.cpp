#include "localization/slam/feature/frame_features.hpp"

#include <algorithm>
#include <cmath>

namespace labo::slam {

FeatureGrid::FeatureGrid(const Eigen::Vector2d& min, const Eigen::Vector2d& max, double cell_px)
    : min_(min), cell_(cell_px) {
  cols_ = std::max(1, static_cast<int>(std::ceil((max.x() - min.x()) / cell_)) + 1);
  rows_ = std::max(1, static_cast<int>(std::ceil((max.y() - min.y()) / cell_)) + 1);
  cells_.resize(static_cast<std::size_t>(cols_ * rows_));
}

void FeatureGrid::build(const FrameFeatures& frame) {
  for (auto& c : cells_) c.clear();
  for (std::size_t i = 0; i < frame.features.size(); ++i) {
    const Eigen::Vector2d& p = frame.features[i].px;
    const int cx = std::clamp(static_cast<int>((p.x() - min_.x()) / cell_), 0, cols_ - 1);
    const int cy = std::clamp(static_cast<int>((p.y() - min_.y()) / cell_), 0, rows_ - 1);
    cells_[static_cast<std::size_t>(cy * cols_ + cx)].push_back(static_cast<int>(i));
  }
}

void FeatureGrid::query(const Eigen::Vector2d& px, double radius, int min_level, int max_level,
                        const FrameFeatures& frame, std::vector<int>& out) const {
  out.clear();
  const int x0 = std::max(0, static_cast<int>((px.x() - radius - min_.x()) / cell_));
  const int x1 = std::min(cols_ - 1, static_cast<int>((px.x() + radius - min_.x()) / cell_));
  const int y0 = std::max(0, static_cast<int>((px.y() - radius - min_.y()) / cell_));
  const int y1 = std::min(rows_ - 1, static_cast<int>((px.y() + radius - min_.y()) / cell_));
  const double r2 = radius * radius;
  for (int y = y0; y <= y1; ++y) {
    for (int x = x0; x <= x1; ++x) {
      for (int i : cells_[static_cast<std::size_t>(y * cols_ + x)]) {
        const Feature& f = frame.features[static_cast<std::size_t>(i)];
        if (f.level < min_level || f.level > max_level) continue;
        if ((f.px - px).squaredNorm() <= r2) out.push_back(i);
      }
    }
  }
}

}  // namespace labo::slam
