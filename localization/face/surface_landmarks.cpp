#include "localization/face/surface_landmarks.hpp"

#include <limits>
#include <optional>
#include <span>
#include <stdexcept>

namespace labo::face {

namespace {

// Distance along the ray (origin o, unit direction d) to triangle (a, b, c), either side; none when
// the ray misses it (Moeller-Trumbore).
std::optional<double> ray_hit(const Eigen::Vector3d& o, const Eigen::Vector3d& d, const Eigen::Vector3d& a,
                              const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const Eigen::Vector3d e1 = b - a, e2 = c - a;
  const Eigen::Vector3d p = d.cross(e2);
  const double det = e1.dot(p);
  if (std::abs(det) < 1e-12) return std::nullopt;
  const double inv = 1.0 / det;
  const Eigen::Vector3d s = o - a;
  const double u = s.dot(p) * inv;
  if (u < 0 || u > 1) return std::nullopt;
  const Eigen::Vector3d q = s.cross(e1);
  const double v = d.dot(q) * inv;
  if (v < 0 || u + v > 1) return std::nullopt;
  const double t = e2.dot(q) * inv;
  if (t <= 0) return std::nullopt;
  return t;
}

double eye_centre_distance(const FaceLandmarkModel& model, const Eigen::Matrix3Xd& points) {
  Eigen::Vector3d right = Eigen::Vector3d::Zero(), left = Eigen::Vector3d::Zero();
  for (int id = 36; id < 42; ++id) right += points.col(model.column_of(id)) / 6.0;
  for (int id = 42; id < 48; ++id) left += points.col(model.column_of(id)) / 6.0;
  return (left - right).norm();
}

}  // namespace

Eigen::Matrix3Xd surface_landmark_offsets(const Candide3Model& candide, const FaceLandmarkModel& model,
                                          const Eigen::VectorXd& tau, double ipd_m, const Eigen::Isometry3d& T_cam_face,
                                          const Eigen::Matrix2Xd& ideal_pixels, const IdealPinhole& camera,
                                          double max_offset_m) {
  if (ideal_pixels.cols() != model.size()) {
    throw std::invalid_argument("surface landmarks: " + std::to_string(ideal_pixels.cols()) + " pixels, the model has " +
                                std::to_string(model.size()) + " landmarks");
  }
  const double mpu = model.metres_per_unit(tau, ipd_m);
  std::vector<Eigen::Vector3d> mesh = candide.deformed(std::span<const double>(tau.data(), static_cast<std::size_t>(tau.size())));
  for (auto& v : mesh) v *= mpu;
  const Eigen::Matrix3Xd mapped = model.points_m(tau, ipd_m);
  const Eigen::Isometry3d T_face_cam = T_cam_face.inverse();
  const Eigen::Vector3d origin = T_face_cam.translation();
  Eigen::Matrix3Xd offsets = Eigen::Matrix3Xd::Zero(3, model.size());
  for (Eigen::Index i = 0; i < model.size(); ++i) {
    const Eigen::Vector3d ray_cam((ideal_pixels(0, i) - camera.cx) / camera.fx, (ideal_pixels(1, i) - camera.cy) / camera.fy, 1.0);
    const Eigen::Vector3d d = (T_face_cam.linear() * ray_cam).normalized();
    double nearest = std::numeric_limits<double>::infinity();
    for (const auto& tri : candide.triangles()) {
      const auto t = ray_hit(origin, d, mesh[static_cast<std::size_t>(tri[0])], mesh[static_cast<std::size_t>(tri[1])],
                             mesh[static_cast<std::size_t>(tri[2])]);
      if (t && *t < nearest) nearest = *t;
    }
    if (!std::isfinite(nearest)) continue;  // past the face: keep the mapped point
    // Where the ray meets the fitted mesh: the picture's position on the face's surface. The depth
    // is the mesh's there, not the mapped vertex's: a brow end seen on the temple lies ~10 mm deeper
    // than the brow vertex the mapping names, which a frontal picture cannot tell otherwise and which
    // showed as a pitch bias (docs/face.md, "Pitch").
    const Eigen::Vector3d offset = origin + nearest * d - mapped.col(i);
    // The limit is on what the picture saw, the in-plane part: the depth is the mesh's, and an outer
    // brow end seen on the temple lies 10-15 mm deeper than the brow vertex (a limit on the whole
    // offset would send it back to the vertex, and its pitch bias with it; docs/face.md).
    if (offset.head<2>().norm() <= max_offset_m) offsets.col(i) = offset;
  }
  // The metric scale stays the interpupillary distance's: the offsets move the eye landmarks too
  // (by the picture's detection noise), so the moved points are scaled about the face origin back to
  // the mapped eye centres' distance.
  const Eigen::Matrix3Xd moved = mapped + offsets;
  return moved * (eye_centre_distance(model, mapped) / eye_centre_distance(model, moved)) - mapped;
}

}  // namespace labo::face
