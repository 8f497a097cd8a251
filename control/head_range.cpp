#include "control/head_range.hpp"

#include <algorithm>
#include <cmath>

namespace labo::control {

namespace {
// The learnt height's newest face weighs 1/kHeightWindow once that many are in: a walk's bob (+-2 cm) and the pose's
// depth noise average out; a teacher who sits down is followed within a few seconds of faces.
constexpr int kHeightWindow = 30;
// The face's height between posed faces (the gait's bob, a nod) and the altimeter's error.
constexpr double kHeightSigmaM = 0.06;
// The ray's slope error: the front camera's mounting tilt is not calibrated (up to 2 degrees), and
// the attitude's own error.
constexpr double kRaySigmaRad = 0.035;
// The patch's scale: right when it was learnt from a posed face, drifting as the head turns under
// the adapting template.
constexpr double kScaleSigmaFraction = 0.10;
constexpr double kScaleSigmaGrowthPerS = 0.05;
constexpr double kOutlierSigmas = 2.0;
// A ray this level gives no distance from height.
constexpr double kMinSlope = 0.02;
constexpr double kMinRangeM = 0.3;
}  // namespace

void HeadRange::learn(const Eigen::Vector3d& face_world) {
  faces_ = std::min(faces_ + 1, kHeightWindow);
  face_z_m_ += (face_world.z() - face_z_m_) / faces_;
}

Eigen::Vector3d HeadRange::place(const Eigen::Vector3d& camera_world, const Eigen::Vector3d& head_world, Seconds since_posed_s) const {
  const Eigen::Vector3d ray = head_world - camera_world;
  const double scale_range = ray.norm();
  if (!knows_height() || scale_range < 1e-6) return head_world;
  const Eigen::Vector3d u = ray / scale_range;
  if (std::abs(u.z()) < kMinSlope) return head_world;
  const double height_range = (face_z_m_ - camera_world.z()) / u.z();
  // The face's height on the other side of the camera from the ray: the head is not the teacher's, or
  // the height no longer holds (the teacher sat down under a drone flying low).
  if (height_range < kMinRangeM) return head_world;
  const double height_sigma = std::hypot(kHeightSigmaM, height_range * kRaySigmaRad) / std::abs(u.z());
  // The scale's error is a fraction of the distance; of the true one, for which the height's is the
  // better guess (of the scale's own, a patch that reads the head near would be the more trusted).
  const double scale_sigma = height_range * (kScaleSigmaFraction + kScaleSigmaGrowthPerS * std::max(0.0, since_posed_s));
  // A scale this far off has drifted away (on a patch of background): it is not averaged in.
  if (std::abs(scale_range - height_range) > kOutlierSigmas * std::hypot(height_sigma, scale_sigma)) return camera_world + height_range * u;
  const double w_height = 1.0 / (height_sigma * height_sigma), w_scale = 1.0 / (scale_sigma * scale_sigma);
  const double range = (w_height * height_range + w_scale * scale_range) / (w_height + w_scale);
  return camera_world + range * u;
}

}  // namespace labo::control
