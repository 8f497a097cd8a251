#include "localization/face/face_landmark_model.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace labo::face {

std::vector<int> rigid_landmark_ids() {
  std::vector<int> ids;
  for (int i = 17; i <= 59; ++i) ids.push_back(i);
  return ids;
}

FaceLandmarkModel::FaceLandmarkModel(std::vector<int> landmark_ids, Eigen::Matrix3Xd mean_units,
                                     Eigen::MatrixXd shape_basis, std::vector<std::string> shape_unit_names)
    : landmark_ids_(std::move(landmark_ids)),
      mean_units_(std::move(mean_units)),
      shape_basis_(std::move(shape_basis)),
      shape_unit_names_(std::move(shape_unit_names)) {
  const auto n = static_cast<Eigen::Index>(landmark_ids_.size());
  if (mean_units_.cols() != n || shape_basis_.rows() != 3 * n) {
    throw std::invalid_argument("face landmark model: " + std::to_string(n) + " landmarks but " +
                                std::to_string(mean_units_.cols()) + " mean points and " +
                                std::to_string(shape_basis_.rows()) + " basis rows (expected 3 per landmark)");
  }
  if (static_cast<Eigen::Index>(shape_unit_names_.size()) != shape_basis_.cols()) {
    throw std::invalid_argument("face landmark model: " + std::to_string(shape_basis_.cols()) +
                                " shape units but " + std::to_string(shape_unit_names_.size()) + " names");
  }
  // iBUG: 36-41 the subject's right eye, 42-47 the left eye.
  for (int id = 36; id <= 41; ++id) {
    if (column_of(id) >= 0) right_eye_cols_.push_back(column_of(id));
  }
  for (int id = 42; id <= 47; ++id) {
    if (column_of(id) >= 0) left_eye_cols_.push_back(column_of(id));
  }
  if (right_eye_cols_.size() != 6 || left_eye_cols_.size() != 6) {
    throw std::invalid_argument("face landmark model: needs the twelve eye landmarks 36-47 for the metric scale");
  }
}

int FaceLandmarkModel::column_of(int id) const {
  const auto it = std::find(landmark_ids_.begin(), landmark_ids_.end(), id);
  return it == landmark_ids_.end() ? -1 : static_cast<int>(it - landmark_ids_.begin());
}

Eigen::Matrix3Xd FaceLandmarkModel::points_units(const Eigen::VectorXd& tau) const {
  if (tau.size() != shape_basis_.cols()) {
    throw std::invalid_argument("face landmark model: " + std::to_string(tau.size()) + " shape parameters, expected " +
                                std::to_string(shape_basis_.cols()));
  }
  const Eigen::VectorXd flat = shape_basis_ * tau;
  return mean_units_ + Eigen::Map<const Eigen::Matrix3Xd>(flat.data(), 3, mean_units_.cols());
}

double FaceLandmarkModel::interpupillary_units(const Eigen::VectorXd& tau) const {
  const Eigen::Matrix3Xd p = points_units(tau);
  Eigen::Vector3d right = Eigen::Vector3d::Zero(), left = Eigen::Vector3d::Zero();
  for (int c : right_eye_cols_) right += p.col(c);
  for (int c : left_eye_cols_) left += p.col(c);
  return ((left - right) / 6.0).norm();
}

double FaceLandmarkModel::metres_per_unit(const Eigen::VectorXd& tau, double ipd_m) const {
  return ipd_m / interpupillary_units(tau);
}

Eigen::Matrix3Xd FaceLandmarkModel::points_m(const Eigen::VectorXd& tau, double ipd_m) const {
  return points_units(tau) * metres_per_unit(tau, ipd_m);
}

std::vector<bool> FaceLandmarkModel::observable_units(int min_points, double min_motion) const {
  std::vector<bool> observable(static_cast<std::size_t>(shape_basis_.cols()), false);
  for (Eigen::Index u = 0; u < shape_basis_.cols(); ++u) {
    int moved = 0;
    for (Eigen::Index i = 0; i < mean_units_.cols(); ++i) {
      const double dx = shape_basis_(3 * i, u), dy = shape_basis_(3 * i + 1, u);
      if (std::hypot(dx, dy) > min_motion) ++moved;
    }
    observable[static_cast<std::size_t>(u)] = moved >= min_points;
  }
  return observable;
}

FaceLandmarkModel make_face_landmark_model(const Candide3Model& model, const Ibug68Mapping& mapping,
                                           const std::vector<int>& landmark_ids) {
  const auto n = static_cast<Eigen::Index>(landmark_ids.size());
  const auto m = static_cast<Eigen::Index>(model.shape_units().size());
  Eigen::Matrix3Xd mean(3, n);
  Eigen::MatrixXd basis = Eigen::MatrixXd::Zero(3 * n, m);
  // Per vertex, its displacement under each shape unit (dense: 113 x 14 is small).
  std::vector<Eigen::Matrix3Xd> unit_delta(model.vertices().size(), Eigen::Matrix3Xd::Zero(3, m));
  for (Eigen::Index u = 0; u < m; ++u) {
    for (const auto& d : model.shape_units()[static_cast<std::size_t>(u)].displacements) {
      unit_delta[static_cast<std::size_t>(d.vertex)].col(u) += d.delta;
    }
  }
  for (Eigen::Index i = 0; i < n; ++i) {
    const int id = landmark_ids[static_cast<std::size_t>(i)];
    if (id < 0 || id >= 68) throw std::invalid_argument("face landmark model: landmark " + std::to_string(id) + " is outside 0-67");
    const LandmarkVertexMap& map = mapping[static_cast<std::size_t>(id)];
    if (map.kind == LandmarkVertexMap::Kind::None || map.vertices.empty()) {
      throw std::invalid_argument("face landmark model: landmark " + std::to_string(id) + " has no CANDIDE-3 vertex");
    }
    mean.col(i) = landmark_point(map, model.vertices());
    for (std::size_t k = 0; k < map.vertices.size(); ++k) {
      const auto& delta = unit_delta[static_cast<std::size_t>(map.vertices[k])];
      basis.block(3 * i, 0, 3, m) += map.weights[k] * delta;
    }
  }
  std::vector<std::string> names;
  for (const auto& u : model.shape_units()) names.push_back(u.name);
  return FaceLandmarkModel(landmark_ids, std::move(mean), std::move(basis), std::move(names));
}

}  // namespace labo::face
