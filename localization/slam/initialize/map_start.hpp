#pragma once
// The map from the initializer's two views: keyframes 0 (the reference, whose camera frame is the
// map's) and 1, a point per two-view match, one two-view adjustment, then the map rescaled so that
// the median depth seen from keyframe 0 is 1 (the map's unit; the state estimator makes it metric).
#include "localization/slam/initialize/map_initializer.hpp"
#include "localization/slam/map/slam_map.hpp"
#include "localization/slam/module/local_mapper.hpp"

namespace labo::slam {

// `reference` brings the reference frame's images and IMU attitude (its time and features are
// init's); `current` the completing frame's time, features, images and attitude (its pose is
// init's). The map must be empty.
void start_map(const InitialMap& init, Keyframe reference, Keyframe current, SlamMap& map, LocalMapper& mapper);

}  // namespace labo::slam
