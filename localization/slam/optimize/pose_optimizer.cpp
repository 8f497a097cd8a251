#include "localization/slam/optimize/pose_optimizer.hpp"

#include <cmath>

#include "localization/slam/optimize/se3.hpp"

namespace labo::slam {

int optimize_pose(const IdealCamera& camera, std::vector<PoseObservation>& observations,
                  Eigen::Isometry3d& T, const PoseOptimizerSettings& settings, const std::optional<GravityPrior>& gravity) {
  for (auto& o : observations) o.inlier = true;
  const double fx = camera.fx(), fy = camera.fy(), cx = camera.cx(), cy = camera.cy();
  int inliers = 0;
  for (int round = 0; round < settings.rounds; ++round) {
    for (int it = 0; it < settings.iterations; ++it) {
      Eigen::Matrix<double, 6, 6> H = Eigen::Matrix<double, 6, 6>::Zero();
      Eigen::Matrix<double, 6, 1> g = Eigen::Matrix<double, 6, 1>::Zero();
      int used = 0;
      for (const auto& o : observations) {
        if (!o.inlier) continue;
        const Eigen::Vector3d p = T * o.p_map;
        if (p.z() <= 1e-6) continue;
        const double iz = 1.0 / p.z();
        const Eigen::Vector2d r(o.px.x() - (fx * p.x() * iz + cx), o.px.y() - (fy * p.y() * iz + cy));
        // d(projection)/d(p) times d(p)/d(twist) for T' = exp(twist) * T.
        Eigen::Matrix<double, 2, 3> Jp;
        Jp << fx * iz, 0, -fx * p.x() * iz * iz, 0, fy * iz, -fy * p.y() * iz * iz;
        Eigen::Matrix<double, 3, 6> Jt;
        Jt << Eigen::Matrix3d::Identity(), Eigen::Matrix3d::Zero();
        Jt(0, 4) = p.z();
        Jt(0, 5) = -p.y();
        Jt(1, 3) = -p.z();
        Jt(1, 5) = p.x();
        Jt(2, 3) = p.y();
        Jt(2, 4) = -p.x();
        const Eigen::Matrix<double, 2, 6> J = Jp * Jt;
        const double inv_s2 = 1.0 / (o.sigma * o.sigma);
        const double e = std::sqrt(r.squaredNorm() * inv_s2);
        const double w = (e <= settings.huber_px ? 1.0 : settings.huber_px / e) * inv_s2;
        H.noalias() += w * J.transpose() * J;
        g.noalias() += w * J.transpose() * r;
        ++used;
      }
      if (used < 4) return 0;
      if (gravity) {
        // d(R * down_map)/d(rotation twist) = -[R * down_map]x: rotation block only.
        const Eigen::Vector3d d = T.linear() * gravity->down_map;
        const Eigen::Vector3d r = gravity->down_cam - d;
        Eigen::Matrix3d J;
        J << 0, d.z(), -d.y(), -d.z(), 0, d.x(), d.y(), -d.x(), 0;
        const double w = 1.0 / (gravity->sigma_rad * gravity->sigma_rad);
        H.bottomRightCorner<3, 3>().noalias() += w * J.transpose() * J;
        g.tail<3>().noalias() += w * J.transpose() * r;
      }
      const Eigen::Matrix<double, 6, 1> dx = H.ldlt().solve(g);
      if (!dx.allFinite()) return 0;
      T = se3_exp(dx) * T;
      if (dx.squaredNorm() < 1e-12) break;
    }
    inliers = 0;
    for (auto& o : observations) {
      const Eigen::Vector3d p = T * o.p_map;
      const auto px = camera.project(p);
      const double chi2 = px ? (*px - o.px).squaredNorm() / (o.sigma * o.sigma) : 1e9;
      o.inlier = chi2 <= settings.chi2_gate;
      inliers += o.inlier ? 1 : 0;
    }
  }
  return inliers;
}

}  // namespace labo::slam
