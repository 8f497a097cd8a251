#include "localization/slam/initialize/two_view_geometry.hpp"

#include <algorithm>
#include <cmath>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>

namespace labo::slam {
namespace {

constexpr double kChi2OneDof = 3.84, kChi2TwoDof = 5.99;

// Truncated transfer score of a homography (both directions), higher is better.
double homography_score(const cv::Mat& H, const std::vector<cv::Point2f>& a, const std::vector<cv::Point2f>& b, double sigma) {
  cv::Matx33d h(H), hi = h.inv();
  double score = 0;
  auto transfer = [](const cv::Matx33d& m, const cv::Point2f& p) {
    const cv::Vec3d q = m * cv::Vec3d(p.x, p.y, 1.0);
    return cv::Point2d(q[0] / q[2], q[1] / q[2]);
  };
  for (std::size_t i = 0; i < a.size(); ++i) {
    const cv::Point2d ab = transfer(h, a[i]) - cv::Point2d(b[i]);
    const cv::Point2d ba = transfer(hi, b[i]) - cv::Point2d(a[i]);
    const double e1 = ab.dot(ab) / (sigma * sigma), e2 = ba.dot(ba) / (sigma * sigma);
    score += std::max(0.0, kChi2TwoDof - e1) + std::max(0.0, kChi2TwoDof - e2);
  }
  return score;
}

// The same for a fundamental matrix: point-to-epipolar-line distances, 1-dof gate, 2-dof offset so
// the two models' scores are comparable.
double fundamental_score(const cv::Matx33d& F, const std::vector<cv::Point2f>& a, const std::vector<cv::Point2f>& b, double sigma) {
  double score = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const cv::Vec3d pa(a[i].x, a[i].y, 1), pb(b[i].x, b[i].y, 1);
    const cv::Vec3d lb = F * pa, la = F.t() * pb;
    const double nb = lb[0] * lb[0] + lb[1] * lb[1], na = la[0] * la[0] + la[1] * la[1];
    if (nb <= 0 || na <= 0) continue;
    const double d = pb.dot(lb);
    const double e1 = d * d / nb / (sigma * sigma), e2 = d * d / na / (sigma * sigma);
    if (e1 < kChi2OneDof) score += kChi2TwoDof - e1;
    if (e2 < kChi2OneDof) score += kChi2TwoDof - e2;
  }
  return score;
}

struct Triangulated {
  std::vector<int> index;
  std::vector<Eigen::Vector3d> points;
  double median_parallax_deg = 0;
};

Triangulated triangulate_all(const IdealCamera& camera, const Eigen::Isometry3d& T21, const std::vector<Eigen::Vector2d>& first,
                             const std::vector<Eigen::Vector2d>& second, double max_error_px) {
  Triangulated out;
  std::vector<double> parallax;
  const Eigen::Vector3d c2 = T21.inverse().translation();
  for (std::size_t i = 0; i < first.size(); ++i) {
    const auto p = triangulate(camera, Eigen::Isometry3d::Identity(), first[i], T21, second[i]);
    if (!p) continue;
    const auto a = camera.project(*p), b = camera.project(T21 * *p);
    if (!a || !b || (*a - first[i]).norm() > max_error_px || (*b - second[i]).norm() > max_error_px) continue;
    const double cos_angle = p->normalized().dot((*p - c2).normalized());
    out.index.push_back(static_cast<int>(i));
    out.points.push_back(*p);
    parallax.push_back(std::acos(std::clamp(cos_angle, -1.0, 1.0)) * 180.0 / M_PI);
  }
  if (!parallax.empty()) {
    std::nth_element(parallax.begin(), parallax.begin() + static_cast<long>(parallax.size() / 2), parallax.end());
    out.median_parallax_deg = parallax[parallax.size() / 2];
  }
  return out;
}

Eigen::Isometry3d to_isometry(const cv::Mat& R, const cv::Mat& t) {
  Eigen::Matrix3d r;
  Eigen::Vector3d v;
  cv::cv2eigen(R, r);
  cv::cv2eigen(t, v);
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = r;
  T.translation() = v.normalized();
  return T;
}

}  // namespace

std::optional<Eigen::Vector3d> triangulate(const IdealCamera& camera, const Eigen::Isometry3d& T_a, const Eigen::Vector2d& px_a,
                                           const Eigen::Isometry3d& T_b, const Eigen::Vector2d& px_b) {
  const Eigen::Vector3d ra = camera.bearing(px_a), rb = camera.bearing(px_b);
  Eigen::Matrix4d A;
  const Eigen::Matrix<double, 3, 4> Pa = T_a.matrix().topRows<3>(), Pb = T_b.matrix().topRows<3>();
  A.row(0) = ra.x() * Pa.row(2) - ra.z() * Pa.row(0);
  A.row(1) = ra.y() * Pa.row(2) - ra.z() * Pa.row(1);
  A.row(2) = rb.x() * Pb.row(2) - rb.z() * Pb.row(0);
  A.row(3) = rb.y() * Pb.row(2) - rb.z() * Pb.row(1);
  const Eigen::Vector4d X = Eigen::JacobiSVD<Eigen::Matrix4d>(A, Eigen::ComputeFullV).matrixV().col(3);
  if (std::abs(X.w()) < 1e-12) return std::nullopt;
  const Eigen::Vector3d p = X.head<3>() / X.w();
  if (!p.allFinite() || (T_a * p).z() <= 0 || (T_b * p).z() <= 0) return std::nullopt;
  return p;
}

TwoViewOutcome reconstruct_two_views(const IdealCamera& camera, const std::vector<Eigen::Vector2d>& first,
                                     const std::vector<Eigen::Vector2d>& second, const TwoViewSettings& settings) {
  TwoViewOutcome outcome;
  if (first.size() < static_cast<std::size_t>(settings.min_points)) {
    outcome.reason = "too few matches (" + std::to_string(first.size()) + ")";
    return outcome;
  }
  std::vector<cv::Point2f> a, b;
  for (std::size_t i = 0; i < first.size(); ++i) {
    a.emplace_back(static_cast<float>(first[i].x()), static_cast<float>(first[i].y()));
    b.emplace_back(static_cast<float>(second[i].x()), static_cast<float>(second[i].y()));
  }
  const cv::Mat K(camera.K());
  cv::Mat e_mask, h_mask;
  const cv::Mat E = cv::findEssentialMat(a, b, K, cv::RANSAC, 0.999, settings.ransac_threshold_px, e_mask);
  const cv::Mat H = cv::findHomography(a, b, cv::RANSAC, 2.0 * settings.ransac_threshold_px, h_mask, 2000, 0.999);
  if (E.empty() || E.rows != 3) {
    outcome.reason = "no essential matrix";
    return outcome;
  }
  const cv::Matx33d Ki = camera.K().inv();
  const cv::Matx33d F = Ki.t() * cv::Matx33d(E(cv::Rect(0, 0, 3, 3))) * Ki;
  const double s_e = fundamental_score(F, a, b, 1.0);
  const double s_h = H.empty() ? 0.0 : homography_score(H, a, b, 1.0);
  const double share = s_h / std::max(1e-9, s_h + s_e);
  const double max_error = 2.0 * settings.ransac_threshold_px + 1.0;

  std::vector<Eigen::Isometry3d> hypotheses;
  TwoViewModel model = TwoViewModel::Essential;
  if (share > settings.homography_ratio && !H.empty()) {
    model = TwoViewModel::Homography;
    std::vector<cv::Mat> Rs, ts, ns;
    cv::decomposeHomographyMat(H, K, Rs, ts, ns);
    for (std::size_t i = 0; i < Rs.size(); ++i) {
      if (cv::norm(ts[i]) < 1e-9) continue;
      hypotheses.push_back(to_isometry(Rs[i], ts[i]));
    }
  } else {
    cv::Mat R, t;
    cv::recoverPose(E(cv::Rect(0, 0, 3, 3)), a, b, K, R, t, e_mask.clone());
    hypotheses.push_back(to_isometry(R, t));
  }
  // The hypothesis that triangulates the most points wins; a runner-up close to it means the
  // decomposition is ambiguous and we wait for more motion.
  Triangulated best, second_best;
  Eigen::Isometry3d best_T = Eigen::Isometry3d::Identity();
  for (const auto& T : hypotheses) {
    Triangulated tri = triangulate_all(camera, T, first, second, max_error);
    if (tri.index.size() > best.index.size()) {
      second_best = std::move(best);
      best = std::move(tri);
      best_T = T;
    } else if (tri.index.size() > second_best.index.size()) {
      second_best = std::move(tri);
    }
  }
  if (best.index.size() < static_cast<std::size_t>(settings.min_points)) {
    outcome.reason = "only " + std::to_string(best.index.size()) + " points triangulated";
    return outcome;
  }
  if (second_best.index.size() > 0.75 * best.index.size()) {
    outcome.reason = "ambiguous homography decomposition";
    return outcome;
  }
  if (best.median_parallax_deg < settings.min_parallax_deg) {
    outcome.reason = "parallax too small";
    return outcome;
  }
  TwoViewReconstruction r;
  r.model = model;
  r.homography_share = share;
  r.T_second_first = best_T;
  r.match_index = std::move(best.index);
  r.points = std::move(best.points);
  r.median_parallax_deg = best.median_parallax_deg;
  outcome.reconstruction = std::move(r);
  return outcome;
}

}  // namespace labo::slam
