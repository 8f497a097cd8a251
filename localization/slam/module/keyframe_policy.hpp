#pragma once
// When a tracked frame becomes a keyframe (PTAM's rules, with two additions for small maps).
//
// A frame may become a keyframe when its pose is trustworthy: Good, or Dodgy for a reason that
// does not make the pose doubtful. It should become one when the map around it no longer covers the
// view: far from every keyframe, sharing few points with its reference keyframe, or - the small-map
// rule - a reference keyframe holding so few points that the overlap rule could only fire on a frame
// already too poor to be Good. The interval, the map's size limit and the mapper's queue are checked
// by the caller.
#include "localization/slam/slam_system.hpp"

namespace labo::slam {

struct KeyframeCandidate {
  TrackingState state = TrackingState::Lost;
  int found = 0;                    // inliers
  int attempted = 0;                // points searched
  int reference_shared = 0;         // points shared with the reference keyframe
  int reference_points = 0;         // points of the reference keyframe
  double nearest_keyframe_distance = 0;  // map units, camera centre to the nearest keyframe's
  double mean_depth = 0;            // map units, of the found points
};

// The frame's pose is good enough to anchor new map points.
bool keyframe_eligible(const KeyframeCandidate& c, const SlamSettings& s);
// The map needs a keyframe here (geometric need only).
bool keyframe_needed(const KeyframeCandidate& c, const SlamSettings& s);

}  // namespace labo::slam
