#pragma once
// Map files: a lab mapped once can be reused. Binary, little-endian, versioned:
//   "LABOSLAM" u32 version (3) | camera (width, height, fx fy cx cy k1 k2 p1 p2 k3) | keyframes (each
//   ending with its gravity direction) | points | loop edges (u32 count; i32 current, i32 loop, f64 scale,
//   3x3 f64 rotation, 3 f64 translation) | the map's gravity direction | u64 FNV-1a of everything before
//   it | "ENDSLAM!". A gravity direction is u8 present (0/1) then, if present, 3 f64 (a unit vector).
// Version 2 files (no gravity directions) are still read.
// Reading refuses, with the reason: a file too short or cut (truncated), a bad checksum (corrupted),
// a version this build cannot read, a map built with different camera intrinsics, and indices or numbers that do not
// make sense (a keyframe feature that does not exist, non-finite poses).
#include <filesystem>

#include "core/camera_model.hpp"
#include "localization/slam/map/slam_map.hpp"

namespace labo::slam {

void write_map_file(const std::filesystem::path& file, const CameraIntrinsics& camera, const SlamMap& map);
// Fills `out` (which should be empty); throws std::runtime_error naming the file and the reason.
void read_map_file(const std::filesystem::path& file, const CameraIntrinsics& camera, SlamMap& out);

}  // namespace labo::slam
