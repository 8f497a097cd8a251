#pragma once
// Keyframe and MapPoint: what the map is made of. A keyframe keeps its features and descriptors (for
// new points, re-measurement and relocalization) and a small blurry image for ranking keyframes when
// relocalizing, and its image pyramid for the points' patches. A map point keeps its position, a
// representative descriptor and its observations.
#include <Eigen/Geometry>
#include <cstdint>
#include <opencv2/core.hpp>
#include <optional>
#include <vector>

#include "core/time.hpp"
#include "localization/slam/feature/frame_features.hpp"

namespace labo::slam {

using PointId = std::int64_t;
constexpr PointId kNoPoint = -1;

struct Keyframe {
  int id = -1;
  Seconds t = 0;
  Eigen::Isometry3d T_cam_map = Eigen::Isometry3d::Identity();
  FrameFeatures frame;
  std::vector<PointId> point_of_feature;  // one per feature, kNoPoint when none
  cv::Mat small_image;                    // CV_32F, zero mean, blurred (relocalization ranking)
  // The 8-bit pyramid the features were found on (smoothed as extracted): the source of the map
  // points' patches (match/patch_aligner). Not saved: a loaded map's points are tracked from their
  // corners alone.
  std::vector<cv::Mat> pyramid;
  // Set by the tracker, not saved: the map generation its pose was computed in and the tracker's
  // reference keyframe, so that a loop correction made while it was queued can be applied to it.
  int map_generation = 0;
  int tracking_reference = -1;
  // The IMU's gravity direction ("down", unit vector) in this keyframe's camera frame when the frame
  // came with an attitude: the gravity prior of the adjustments. Saved with the map (version 3).
  std::optional<Eigen::Vector3d> down_cam;

  Eigen::Vector3d center() const { return T_cam_map.inverse().translation(); }
  Eigen::Vector3d optical_axis() const { return T_cam_map.linear().row(2).transpose(); }
};

// A pyramid a keyframe can keep: the extractor reuses its buffers (and level 0 may be the caller's frame).
inline std::vector<cv::Mat> owned_pyramid(const std::vector<cv::Mat>& pyramid) {
  std::vector<cv::Mat> out;
  out.reserve(pyramid.size());
  for (const cv::Mat& level : pyramid) out.push_back(level.clone());
  return out;
}

struct Observation {
  int keyframe = -1;
  int feature = -1;
};

struct MapPoint {
  PointId id = kNoPoint;
  Eigen::Vector3d p_map = Eigen::Vector3d::Zero();
  Descriptor descriptor{};
  std::vector<Observation> observations;
  int reference_keyframe = -1;
  int reference_level = 0;
  double reference_distance = 1.0;  // from the reference keyframe's centre when created
  // Mapper's bookkeeping: re-found or not when a new keyframe should have seen the point.
  int remeasure_hits = 0;
  int remeasure_misses = 0;

  int observed_by(int keyframe) const {
    for (const auto& o : observations) {
      if (o.keyframe == keyframe) return o.feature;
    }
    return -1;
  }
};

}  // namespace labo::slam
