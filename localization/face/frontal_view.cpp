#include "localization/face/frontal_view.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "localization/face/face_image_warp.hpp"

namespace labo::face {

namespace {

// The affine map taking triangle (a, b, c) onto (A, B, C); nullopt-like zero matrix when degenerate.
bool affine_between(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c,
                    const Eigen::Vector2d& A, const Eigen::Vector2d& B, const Eigen::Vector2d& C,
                    Eigen::Matrix<double, 2, 3>& out) {
  Eigen::Matrix2d src;
  src << b - a, c - a;
  if (std::abs(src.determinant()) < 1e-9) return false;
  Eigen::Matrix2d dst;
  dst << B - A, C - A;
  const Eigen::Matrix2d L = dst * src.inverse();
  out.leftCols<2>() = L;
  out.col(2) = A - L * a;
  return true;
}

}  // namespace

FrontalView::FrontalView(std::vector<std::array<int, 3>> triangles) : triangles_(std::move(triangles)) {
  triangle_maps_.resize(triangles_.size());
}

void FrontalView::set_vertices(std::vector<Eigen::Vector3d> vertices_m) {
  for (const auto& t : triangles_) {
    for (int v : t) {
      if (v < 0 || static_cast<std::size_t>(v) >= vertices_m.size()) {
        throw std::invalid_argument("frontal view: a triangle names a vertex the mesh does not have");
      }
    }
  }
  vertices_m_ = std::move(vertices_m);
  view_vertices_.resize(2, static_cast<Eigen::Index>(vertices_m_.size()));
  image_vertices_.resize(2, static_cast<Eigen::Index>(vertices_m_.size()));
}

Eigen::Vector2d FrontalView::view_of(const Eigen::Vector3d& p) const {
  // The virtual camera sees the face head-on: R = diag(1, -1, -1), the face's origin on its axis.
  const double z = distance_m_ - p.z();
  return centre_px_ + focal_px_ / z * Eigen::Vector2d(p.x(), -p.y());
}

bool FrontalView::render(const cv::Mat& gray, const PinholeCamera& camera, const Eigen::Isometry3d& T_cam_face,
                         const Eigen::Vector2d& shift_px, double focal_px, cv::Size size) {
  if (vertices_m_.empty()) throw std::logic_error("frontal view: no mesh (set_vertices first)");
  if (gray.empty() || gray.type() != CV_8UC1) throw std::invalid_argument("frontal view: expected an 8-bit grey image");
  if (!(focal_px > 0) || size.width < 8 || size.height < 8) throw std::invalid_argument("frontal view: bad view size or focal length");
  focal_px_ = focal_px;
  distance_m_ = T_cam_face.translation().norm();
  centre_px_ = Eigen::Vector2d(size.width / 2.0 - 0.5, size.height / 2.0 - 0.5);
  for (std::size_t i = 0; i < vertices_m_.size(); ++i) {
    const auto px = camera.project(T_cam_face * vertices_m_[i]);
    if (!px) {
      view_.release();
      return false;
    }
    const auto col = static_cast<Eigen::Index>(i);
    image_vertices_.col(col) = *px + shift_px;
    view_vertices_.col(col) = view_of(vertices_m_[i]);
  }
  // Off the mesh: the least-squares affine map from view to image over all vertices.
  const Eigen::Index n = view_vertices_.cols();
  Eigen::MatrixXd A(n, 3);
  A.leftCols<2>() = view_vertices_.transpose();
  A.col(2).setOnes();
  fallback_map_ = A.colPivHouseholderQr().solve(image_vertices_.transpose()).transpose();
  rasterise(size);
  // As cv::remap (linear, border replicated) computes it, without its per-call allocations.
  remap_8u(gray, map_x_, map_y_, sized_view(view_storage_, size, CV_8UC1, view_));
  return true;
}

void FrontalView::rasterise(cv::Size size) {
  // The view's size follows the face's from frame to frame: views of buffers that only grow.
  // Filled row by row: cv::Mat::setTo allocates on such a view (a region, not continuous).
  sized_view(triangle_id_storage_, size, CV_32SC1, triangle_id_);
  sized_view(depth_storage_, size, CV_32FC1, depth_);
  sized_view(map_x_storage_, size, CV_32FC1, map_x_);
  sized_view(map_y_storage_, size, CV_32FC1, map_y_);
  for (int y = 0; y < size.height; ++y) {
    std::fill_n(triangle_id_.ptr<int>(y), size.width, -1);
    std::fill_n(depth_.ptr<float>(y), size.width, std::numeric_limits<float>::infinity());
  }
  // Off the mesh: the fallback affine map; the triangles overwrite it where they cover the view.
  const Eigen::Matrix<double, 2, 3>& F = fallback_map_;
  for (int y = 0; y < size.height; ++y) {
    auto* mx = map_x_.ptr<float>(y);
    auto* my = map_y_.ptr<float>(y);
    for (int x = 0; x < size.width; ++x) {
      mx[x] = static_cast<float>(F(0, 0) * x + F(0, 1) * y + F(0, 2));
      my[x] = static_cast<float>(F(1, 0) * x + F(1, 1) * y + F(1, 2));
    }
  }
  for (std::size_t t = 0; t < triangles_.size(); ++t) {
    const auto& tri = triangles_[t];
    const Eigen::Vector2d a = view_vertices_.col(tri[0]), b = view_vertices_.col(tri[1]), c = view_vertices_.col(tri[2]);
    if (!affine_between(a, b, c, image_vertices_.col(tri[0]), image_vertices_.col(tri[1]), image_vertices_.col(tri[2]),
                        triangle_maps_[t])) {
      continue;
    }
    const double depth = distance_m_ - (vertices_m_[tri[0]].z() + vertices_m_[tri[1]].z() + vertices_m_[tri[2]].z()) / 3;
    // Barycentric coordinates as linear functions of the pixel, w_i = e_i · (x, y, 1), either winding.
    const double area = (b - a).x() * (c - a).y() - (b - a).y() * (c - a).x();
    const auto edge = [area](const Eigen::Vector2d& p, const Eigen::Vector2d& q) -> Eigen::Vector3d {
      return Eigen::Vector3d(p.y() - q.y(), q.x() - p.x(), p.x() * q.y() - p.y() * q.x()) / area;
    };
    const Eigen::Vector3d e0 = edge(b, c), e1 = edge(c, a);
    const int x0 = std::max(0, static_cast<int>(std::floor(std::min({a.x(), b.x(), c.x()}))));
    const int x1 = std::min(size.width - 1, static_cast<int>(std::ceil(std::max({a.x(), b.x(), c.x()}))));
    const int y0 = std::max(0, static_cast<int>(std::floor(std::min({a.y(), b.y(), c.y()}))));
    const int y1 = std::min(size.height - 1, static_cast<int>(std::ceil(std::max({a.y(), b.y(), c.y()}))));
    const Eigen::Matrix<double, 2, 3>& M = triangle_maps_[t];
    for (int y = y0; y <= y1; ++y) {
      auto* id = triangle_id_.ptr<int>(y);
      auto* d = depth_.ptr<float>(y);
      auto* mx = map_x_.ptr<float>(y);
      auto* my = map_y_.ptr<float>(y);
      double w0 = e0.x() * x0 + e0.y() * y + e0.z(), w1 = e1.x() * x0 + e1.y() * y + e1.z();
      for (int x = x0; x <= x1; ++x, w0 += e0.x(), w1 += e1.x()) {
        if (w0 < -1e-6 || w1 < -1e-6 || 1 - w0 - w1 < -1e-6 || depth >= d[x]) continue;
        d[x] = static_cast<float>(depth);
        id[x] = static_cast<int>(t);
        mx[x] = static_cast<float>(M(0, 0) * x + M(0, 1) * y + M(0, 2));
        my[x] = static_cast<float>(M(1, 0) * x + M(1, 1) * y + M(1, 2));
      }
    }
  }
}

Eigen::Vector2d FrontalView::image_of(const Eigen::Vector2d& v) const {
  if (view_.empty()) throw std::logic_error("frontal view: no view rendered");
  const int x = std::clamp(static_cast<int>(std::lround(v.x())), 0, triangle_id_.cols - 1);
  const int y = std::clamp(static_cast<int>(std::lround(v.y())), 0, triangle_id_.rows - 1);
  int id = triangle_id_.at<int>(y, x);
  // Just off the mesh's rim (the pixel centre outside, the point on or near an edge): the nearest
  // triangle within a few pixels extends continuously; farther out, the global affine map.
  constexpr int kReach = 3;
  for (int r = 1; id < 0 && r <= kReach; ++r) {
    for (int dy = -r; dy <= r && id < 0; ++dy) {
      for (int dx = -r; dx <= r && id < 0; ++dx) {
        const int xx = x + dx, yy = y + dy;
        if (xx >= 0 && yy >= 0 && xx < triangle_id_.cols && yy < triangle_id_.rows) id = triangle_id_.at<int>(yy, xx);
      }
    }
  }
  const Eigen::Matrix<double, 2, 3>& M = id >= 0 ? triangle_maps_[static_cast<std::size_t>(id)] : fallback_map_;
  return M * Eigen::Vector3d(v.x(), v.y(), 1);
}

}  // namespace labo::face
