#include "localization/slam/module/relocalizer.hpp"

#include <algorithm>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>
#include <opencv2/imgproc.hpp>

#include "localization/slam/optimize/pose_optimizer.hpp"

namespace labo::slam {

namespace {

// The two smallest Hamming distances from `query` to the frame's descriptors and the index of the
// first at the smallest (ties keep the earlier one). Relocalization's brute-force search spends most
// of its time here, so it is compiled twice: with the POPCNT instruction, chosen at load time where
// the CPU has it, and for the x86-64 baseline (the SWAR count); both give the same integers.
struct NearestTwo {
  int best = 257, second = 257, index = -1;
};

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
__attribute__((target_clones("popcnt", "default")))
#endif
NearestTwo nearest_two(const Descriptor& query, const std::vector<Descriptor>& candidates) {
  std::uint64_t q[4];
  __builtin_memcpy(q, query.data(), sizeof q);
  NearestTwo n;
  for (std::size_t j = 0; j < candidates.size(); ++j) {
    std::uint64_t c[4];
    __builtin_memcpy(c, candidates[j].data(), sizeof c);
    const int d = __builtin_popcountll(q[0] ^ c[0]) + __builtin_popcountll(q[1] ^ c[1]) +
                  __builtin_popcountll(q[2] ^ c[2]) + __builtin_popcountll(q[3] ^ c[3]);
    if (d < n.best) {
      n.second = n.best;
      n.best = d;
      n.index = static_cast<int>(j);
    } else if (d < n.second) {
      n.second = d;
    }
  }
  return n;
}

}  // namespace

cv::Mat small_blurry_image(const cv::Mat& gray) {
  cv::Mat small, blurred;
  const int w = 40, h = std::max(1, static_cast<int>(std::lround(40.0 * gray.rows / gray.cols)));
  cv::resize(gray, small, cv::Size(w, h), 0, 0, cv::INTER_AREA);
  small.convertTo(blurred, CV_32F);
  cv::GaussianBlur(blurred, blurred, cv::Size(5, 5), 1.0);
  blurred -= cv::mean(blurred)[0];
  return blurred;
}

Relocalizer::Relocalizer(const IdealCamera& camera, int keyframes_tried) : camera_(camera), keyframes_tried_(keyframes_tried) {}

std::optional<RelocalizationCandidate> Relocalizer::relocalize(const SlamMap& map, const FrameFeatures& frame,
                                                               const cv::Mat& small_image) const {
  std::shared_lock lock(map.mutex());
  std::vector<std::pair<double, int>> ranked;
  for (const Keyframe& kf : map.keyframes()) {
    if (kf.small_image.size() != small_image.size()) continue;
    ranked.emplace_back(cv::norm(kf.small_image, small_image, cv::NORM_L2SQR), kf.id);
  }
  std::sort(ranked.begin(), ranked.end());
  std::optional<RelocalizationCandidate> best;
  for (int rank = 0; rank < std::min<int>(keyframes_tried_, static_cast<int>(ranked.size())); ++rank) {
    const Keyframe& kf = map.keyframes()[static_cast<std::size_t>(ranked[static_cast<std::size_t>(rank)].second)];
    std::vector<cv::Point3f> object;
    std::vector<cv::Point2f> image;
    std::vector<PoseObservation> observations;
    for (std::size_t i = 0; i < kf.frame.size(); ++i) {
      const MapPoint* p = map.point(kf.point_of_feature[i]);
      if (!p) continue;
      const NearestTwo n = nearest_two(kf.frame.descriptors[i], frame.descriptors);
      if (n.index < 0 || n.best > 60 || n.best > 0.8 * n.second) continue;
      const Feature& f = frame.features[static_cast<std::size_t>(n.index)];
      object.emplace_back(static_cast<float>(p->p_map.x()), static_cast<float>(p->p_map.y()), static_cast<float>(p->p_map.z()));
      image.emplace_back(static_cast<float>(f.px.x()), static_cast<float>(f.px.y()));
      observations.push_back({p->p_map, f.px, std::pow(1.5, f.level), true});
    }
    if (object.size() < 15) continue;
    cv::Mat rvec, tvec;
    std::vector<int> inliers;
    if (!cv::solvePnPRansac(object, image, cv::Mat(camera_.K()), cv::noArray(), rvec, tvec, false, 200, 4.0f, 0.99,
                            inliers, cv::SOLVEPNP_EPNP) ||
        inliers.size() < 12) {
      continue;
    }
    cv::Mat R;
    cv::Rodrigues(rvec, R);
    Eigen::Matrix3d r;
    Eigen::Vector3d t;
    cv::cv2eigen(R, r);
    cv::cv2eigen(tvec, t);
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = r;
    T.translation() = t;
    const int refined = optimize_pose(camera_, observations, T);
    if (refined < 12) continue;
    if (!best || refined > best->inliers) best = RelocalizationCandidate{T, kf.id, refined};
  }
  return best;
}

}  // namespace labo::slam
