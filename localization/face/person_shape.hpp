#pragma once
// A person's fitted face: CANDIDE-3 shape parameters and the interpupillary distance that sets the
// model's metric scale. Stored one JSON file per person (<people_dir>/<name>.json).
#include <Eigen/Core>
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
};

// Names are 1-64 characters of [A-Za-z0-9_-] (they become file names); throws std::invalid_argument.
void validate_person_name(const std::string& name);
std::filesystem::path person_shape_path(const std::filesystem::path& people_dir, const std::string& name);
// Throws std::runtime_error naming the file and the problem.
void save_person_shape(const PersonShape& person, const std::filesystem::path& file);
// Throws std::runtime_error naming the file, the key and what was expected (`shape_unit_count`
// parameters, |τs| <= 1, interpupillary distance 40-90 mm, landmark offsets [x, y, z] of at most
// 30 mm each).
PersonShape load_person_shape(const std::filesystem::path& file, int shape_unit_count);

}  // namespace labo::face
