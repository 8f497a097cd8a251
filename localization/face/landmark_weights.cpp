#include "localization/face/landmark_weights.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace labo::face {

double landmark_noise_iod(int id) {
  if (id < 17 || id > 59) throw std::invalid_argument("landmark weights: iBUG id " + std::to_string(id) + " is not a rigid landmark (17-59)");
  if (id == 17 || id == 26) return 0.040;  // outer brow ends: on the face's contour
  if (id <= 26) return 0.022;              // the rest of the brows
  if (id <= 47) return 0.014;              // nose ridge and base, eyes
  if (id == 48 || id == 54) return 0.025;  // mouth corners
  return 0.018;                            // outer lips
}

Eigen::VectorXd landmark_noise_weights(const std::vector<int>& ids) {
  constexpr double kReference = 0.014;
  Eigen::VectorXd w(static_cast<Eigen::Index>(ids.size()));
  for (std::size_t i = 0; i < ids.size(); ++i) {
    const double ratio = kReference / landmark_noise_iod(ids[i]);
    w(static_cast<Eigen::Index>(i)) = ratio * ratio;
  }
  return w;
}

void apply_far_side_weights(const Eigen::Matrix3Xd& points_face, double yaw_rad, double far_side_yaw_rad,
                            Eigen::VectorXd& weights) {
  if (far_side_yaw_rad <= 0) return;
  if (weights.size() != points_face.cols()) throw std::invalid_argument("landmark weights: one weight per point expected");
  const double turn = yaw_rad / far_side_yaw_rad;
  const double away_sign = yaw_rad > 0 ? -1.0 : 1.0;
  for (Eigen::Index i = 0; i < points_face.cols(); ++i) {
    const double away = std::clamp(away_sign * points_face(0, i) / 0.05, 0.0, 1.0);
    weights(i) /= 1.0 + away * turn * turn;
  }
}

}  // namespace labo::face
