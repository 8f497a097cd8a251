#include "bench/slam/trajectory_metrics.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <stdexcept>

namespace labo::bench {

std::optional<Sim3> align_sim3(const std::vector<PosePair>& pairs) {
  if (pairs.size() < 3) return std::nullopt;
  Eigen::Matrix3Xd src(3, static_cast<Eigen::Index>(pairs.size())), dst(3, static_cast<Eigen::Index>(pairs.size()));
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    src.col(static_cast<Eigen::Index>(i)) = pairs[i].estimate_T_map_cam.translation();
    dst.col(static_cast<Eigen::Index>(i)) = pairs[i].truth_T_world_cam.translation();
  }
  const Eigen::Matrix4d T = Eigen::umeyama(src, dst, true);
  if (!T.allFinite()) return std::nullopt;
  Sim3 s;
  s.scale = T.block<3, 1>(0, 0).norm();
  if (!(s.scale > 0)) return std::nullopt;
  s.R = T.block<3, 3>(0, 0) / s.scale;
  s.t = T.block<3, 1>(0, 3);
  return s;
}

namespace {

// Signed sum of the estimated rotations about the true rotation axes, and the true angle turned.
std::pair<double, double> turned_angles(const std::vector<PosePair>& pairs) {
  double estimated = 0, truth = 0;
  for (std::size_t i = 1; i < pairs.size(); ++i) {
    const Eigen::AngleAxisd true_step(pairs[i].truth_T_world_cam.linear().transpose() * pairs[i - 1].truth_T_world_cam.linear());
    const Eigen::AngleAxisd est_step(pairs[i].estimate_T_map_cam.linear().transpose() * pairs[i - 1].estimate_T_map_cam.linear());
    truth += true_step.angle();
    estimated += est_step.angle() * est_step.axis().dot(true_step.axis());
  }
  return {estimated, truth};
}

}  // namespace

std::optional<TrajectoryErrors> trajectory_errors(const std::vector<PosePair>& pairs, Seconds rpe_interval_s) {
  const auto sim = align_sim3(pairs);
  if (!sim) return std::nullopt;
  TrajectoryErrors e;
  e.poses = static_cast<int>(pairs.size());
  e.alignment_scale = sim->scale;
  double sum2 = 0;
  for (const PosePair& p : pairs) {
    const double err = (sim->apply(p.estimate_T_map_cam.translation()) - p.truth_T_world_cam.translation()).norm();
    sum2 += err * err;
    e.ate_max_m = std::max(e.ate_max_m, err);
  }
  e.ate_rmse_m = std::sqrt(sum2 / static_cast<double>(pairs.size()));
  // Relative pose error over the interval (pairs are in time order).
  double t2 = 0, r2 = 0;
  int n = 0;
  std::size_t j = 0;
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    while (j < pairs.size() && pairs[j].t < pairs[i].t + rpe_interval_s) ++j;
    if (j >= pairs.size()) break;
    if (pairs[j].t > pairs[i].t + 1.5 * rpe_interval_s) continue;  // a gap (tracking lost)
    Eigen::Isometry3d est = pairs[i].estimate_T_map_cam.inverse() * pairs[j].estimate_T_map_cam;
    est.translation() *= sim->scale;
    const Eigen::Isometry3d truth = pairs[i].truth_T_world_cam.inverse() * pairs[j].truth_T_world_cam;
    const Eigen::Isometry3d err = truth.inverse() * est;
    t2 += err.translation().squaredNorm();
    const double angle = Eigen::AngleAxisd(err.linear()).angle() * 180.0 / M_PI;
    r2 += angle * angle;
    ++n;
  }
  if (n > 0) {
    e.rpe_translation_rmse_m = std::sqrt(t2 / n);
    e.rpe_rotation_rmse_deg = std::sqrt(r2 / n);
  }
  const auto [estimated_turn, true_turn] = turned_angles(pairs);
  e.truth_turned_deg = true_turn * 180.0 / M_PI;
  if (true_turn > M_PI / 2) e.rotation_scale_error_percent = 100.0 * (estimated_turn / true_turn - 1.0);
  const std::size_t third = pairs.size() / 3;
  if (third >= 10) {
    const auto first = align_sim3({pairs.begin(), pairs.begin() + static_cast<long>(third)});
    const auto last = align_sim3({pairs.end() - static_cast<long>(third), pairs.end()});
    if (first && last) e.scale_drift_percent = 100.0 * std::abs(last->scale / first->scale - 1.0);
  }
  return e;
}

std::vector<double> windowed_ate_m(const std::vector<PosePair>& pairs, Seconds window_s) {
  const auto sim = align_sim3(pairs);
  if (!sim || pairs.empty() || !(window_s > 0)) return {};
  const Seconds t0 = pairs.front().t;
  const auto windows = static_cast<std::size_t>((pairs.back().t - t0) / window_s) + 1;
  std::vector<double> sum2(windows, 0.0);
  std::vector<int> n(windows, 0);
  for (const PosePair& p : pairs) {
    const auto w = static_cast<std::size_t>((p.t - t0) / window_s);
    sum2[w] += (sim->apply(p.estimate_T_map_cam.translation()) - p.truth_T_world_cam.translation()).squaredNorm();
    ++n[w];
  }
  std::vector<double> out(windows, 0.0);
  for (std::size_t w = 0; w < windows; ++w) out[w] = n[w] > 0 ? std::sqrt(sum2[w] / n[w]) : 0.0;
  return out;
}

void write_tum_trajectory(const std::string& file, const std::vector<PosePair>& pairs, bool ground_truth) {
  std::ofstream out(file);
  if (!out) throw std::runtime_error("cannot write trajectory file " + file);
  out << std::setprecision(9);
  for (const PosePair& p : pairs) {
    const Eigen::Isometry3d& T = ground_truth ? p.truth_T_world_cam : p.estimate_T_map_cam;
    const Eigen::Quaterniond q(T.linear());
    out << p.t << ' ' << T.translation().x() << ' ' << T.translation().y() << ' ' << T.translation().z() << ' ' << q.x() << ' '
        << q.y() << ' ' << q.z() << ' ' << q.w() << '\n';
  }
  if (!out) throw std::runtime_error("write failed: " + file);
}

}  // namespace labo::bench
