#pragma once
// A person's fitted face: CANDIDE-3 shape parameters and the interpupillary distance that sets the
// model's metric scale. Stored one JSON file per person (<people_dir>/<name>.json).
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <filesystem>
#include <string>

namespace labo::face {

struct PersonShape {
  std::string name;
  double interpupillary_distance_m = 0.063;
  Eigen::VectorXd shape_params;  // one per CANDIDE-3 shape unit
  double fit_rms_px = 0;         // landmark fit error of the registration picture
  // Per model landmark (3 x n, metres, face frame): where the registration picture's landmarks lie on
  // the fitted mesh, from their mapped points (surface_landmarks.hpp); empty: the mapped points.
  Eigen::Matrix3Xd landmark_offsets_m;
  // The person's frame: the rotation from the fitted model's frame (the shape's points and the offsets
  // above) into the person's own. Registration takes out the fitted pose's roll, so that the head of
  // the registration pictures (upright) is upright (person_registration.cpp). Identity for the generic
  // face and a person stored without it.
  Eigen::Matrix3d R_frontal_model = Eigen::Matrix3d::Identity();
};

// The person's landmarks in their frontal frame (3 x n, metres): `points_m` (the shape's mapped
// points) plus the offsets when there are as many, rotated by R_frontal_model.
Eigen::Matrix3Xd person_landmarks_m(const PersonShape& person, const Eigen::Matrix3Xd& points_m);

// Names are 1-64 characters of [A-Za-z0-9_-] (they become file names); throws std::invalid_argument.
void validate_person_name(const std::string& name);
std::filesystem::path person_shape_path(const std::filesystem::path& people_dir, const std::string& name);
// Throws std::runtime_error naming the file and the problem.
void save_person_shape(const PersonShape& person, const std::filesystem::path& file);
// Throws std::runtime_error naming the file, the key and what was expected (`shape_unit_count`
// parameters, |τs| <= 1, interpupillary distance 40-90 mm, landmark offsets [x, y, z] of at most
// 30 mm each, the registration's pose `frontal_pose_deg` {yaw, pitch, roll} within 30° each).
PersonShape load_person_shape(const std::filesystem::path& file, int shape_unit_count);

}  // namespace labo::face
