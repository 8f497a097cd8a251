#pragma once
// The teacher's head as the simulated lab draws it: a textured triangle mesh in the face frame of
// core/candide3.hpp (+x the subject's left, +y up, +z out of the face; metres). A plain value, so
// that drone/ can draw it without knowing how it was made: localization/face/teacher_head.hpp builds
// it from a photograph (dlib landmarks, CANDIDE-3 fitted to them, each vertex textured with the
// photograph's pixel under it).
#include <Eigen/Core>
#include <array>
#include <functional>
#include <opencv2/core.hpp>
#include <vector>

namespace labo::lab {
struct LabDescription;
}  // namespace labo::lab

namespace labo::sim {

struct TexturedHeadModel {
  std::vector<Eigen::Vector3d> vertices_face_m;
  std::vector<std::array<int, 3>> triangles;
  std::vector<Eigen::Vector2f> texture_px;  // per vertex: pixel of `texture_bgr` (pixel centres at integers)
  cv::Mat texture_bgr;                      // CV_8UC3
};

// Throws std::invalid_argument naming what is wrong: no vertices or triangles, texture coordinates
// not one per vertex, a triangle index out of range, a non-finite vertex, an empty or non-BGR texture.
void validate(const TexturedHeadModel& head);

// Builds the lab's teacher head (from the photograph of the lab's teacher spec); commands in drone/
// take one from their caller, since only localization/ can make it.
using TeacherHeadLoader = std::function<TexturedHeadModel(const lab::LabDescription&)>;

}  // namespace labo::sim
