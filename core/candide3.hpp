#pragma once
// CANDIDE-3 parameterised face model (Ahlberg 2001, config/face/README.md): g = G + S·τs + A·τa.
// Loaded from the published .wfm text file; used by the simulated lab to render the teacher's head
// and by the face pose estimator as its 3D model. Model units and axes as in the file: +x the
// subject's left, +y up, +z out of the face; ~0.61 units between the pupils.
#include <Eigen/Core>
#include <array>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

namespace labo {

class Candide3Model {
 public:
  struct Displacement {
    int vertex = 0;
    Eigen::Vector3d delta = Eigen::Vector3d::Zero();
  };
  // A shape or animation unit: sparse per-vertex displacements for a parameter value of 1.
  struct Unit {
    std::string name;
    std::vector<Displacement> displacements;
  };

  // Throws std::runtime_error naming the file, the line and what was expected.
  static Candide3Model load(const std::filesystem::path& wfm_file);
  // config/face/candide3.wfm of the source tree.
  static std::filesystem::path default_path();

  const std::vector<Eigen::Vector3d>& vertices() const { return vertices_; }
  const std::vector<std::array<int, 3>>& triangles() const { return triangles_; }
  const std::vector<Unit>& shape_units() const { return shape_units_; }
  const std::vector<Unit>& animation_units() const { return animation_units_; }

  // G + S·shape + A·animation. Parameter vectors may be shorter than the unit lists (missing = 0);
  // longer ones throw std::invalid_argument.
  std::vector<Eigen::Vector3d> deformed(std::span<const double> shape_params,
                                        std::span<const double> animation_params = {}) const;
  // The same into a caller's buffer (no allocation once `out` has the right size).
  void deform_into(std::span<const double> shape_params, std::span<const double> animation_params,
                   std::vector<Eigen::Vector3d>& out) const;

 private:
  std::vector<Eigen::Vector3d> vertices_;
  std::vector<std::array<int, 3>> triangles_;
  std::vector<Unit> shape_units_;
  std::vector<Unit> animation_units_;
};

// Which model point stands for each of dlib's 68 landmarks: a weighted sum of vertices (one vertex,
// or a midpoint), or none (most of the jaw contour).
struct LandmarkVertexMap {
  enum class Kind { None, Direct, Interpolated };
  Kind kind = Kind::None;
  std::vector<int> vertices;
  std::vector<double> weights;
};
using Ibug68Mapping = std::array<LandmarkVertexMap, 68>;

// Reads ibug68_to_candide3.csv; throws std::runtime_error naming the file, line and problem,
// including vertex indices outside [0, vertex_count).
Ibug68Mapping load_ibug68_mapping(const std::filesystem::path& csv_file, int vertex_count = 113);
std::filesystem::path default_ibug68_mapping_path();

// The model point of landmark `index` for the given vertices (the weighted sum).
Eigen::Vector3d landmark_point(const LandmarkVertexMap& map, std::span<const Eigen::Vector3d> vertices);

}  // namespace labo
