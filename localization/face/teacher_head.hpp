#pragma once
// The simulated teacher's head from a photograph: the face is found with the estimator's own detector
// and landmarks, CANDIDE-3 is fitted to them (textured_head_renderer.hpp), and the result is handed to
// the simulated lab's renderer as a plain textured mesh (drone/sim/head_model.hpp), in colour.
#include <filesystem>

#include "core/candide3.hpp"
#include "drone/lab/lab_description.hpp"
#include "drone/sim/head_model.hpp"
#include "localization/face/face_config.hpp"

namespace labo::face {

using sim::TexturedHeadModel;

struct TexturedHead;
// The simulated lab's head model of a textured CANDIDE-3 head: the same mesh (vertices, triangles,
// texture coordinates), textured with the colour photograph `photo_bgr` the head was fitted to.
TexturedHeadModel to_head_model(const Candide3Model& candide, const TexturedHead& head, const cv::Mat& photo_bgr);

// Throws std::runtime_error naming the file when the photograph is missing or unreadable, or when no
// face is found in it; std::invalid_argument for an interpupillary distance outside 4-9 cm.
TexturedHeadModel load_teacher_head(const std::filesystem::path& photo, double interpupillary_distance_m,
                                    const FaceConfig& config = default_face_config());

// The lab's teacher: the photograph `teacher.face_image` (relative to the lab file's folder) at the
// teacher's interpupillary distance.
TexturedHeadModel load_lab_teacher_head(const lab::LabDescription& lab, const FaceConfig& config = default_face_config());

}  // namespace labo::face
