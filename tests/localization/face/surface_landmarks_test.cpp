#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>

#include "core/candide3.hpp"
#include "localization/face/face_geometry.hpp"
#include "localization/face/person_shape.hpp"
#include "localization/face/surface_landmarks.hpp"
#include "tests/support/scratch_dir.hpp"

using namespace labo;
using labo::test::ScratchDir;
using namespace labo::face;

namespace {
const IdealPinhole kCamera{569.9, 568.0, 331.4, 135.9};
}  // namespace

TEST_CASE("face: surface landmarks are where the picture's rays meet the mesh, scale kept") {
  const Candide3Model candide = Candide3Model::load(Candide3Model::default_path());
  const FaceLandmarkModel model = make_face_landmark_model(candide, load_ibug68_mapping(default_ibug68_mapping_path()));
  const Eigen::VectorXd tau = Eigen::VectorXd::Zero(model.shape_unit_count());
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = head_rotation({0.0, 0.0, 0.0});
  T.translation() << 0.02, 0.01, 0.8;
  const Eigen::Matrix3Xd mapped = model.points_m(tau, 0.063);
  Eigen::Matrix2Xd px(2, model.size());
  for (Eigen::Index i = 0; i < model.size(); ++i) px.col(i) = kCamera.project(T * mapped.col(i).eval());

  // Landmarks seen exactly where their mapped points project keep them (the mapped points are
  // vertices of the mesh or midpoints of its edges, so on its surface), except the nasion (27):
  // CANDIDE-3's vertex 4 belongs to no triangle and floats 2.3 mm in front of the surface there, and
  // the landmark becomes the surface's point on the same ray.
  const Eigen::Matrix3Xd same = surface_landmark_offsets(candide, model, tau, 0.063, T, px, kCamera, 0.015);
  REQUIRE(same.cols() == model.size());
  for (Eigen::Index i = 0; i < model.size(); ++i) {
    const int id = model.landmark_ids()[static_cast<std::size_t>(i)];
    INFO("landmark " << id << " offset " << same.col(i).transpose());
    CHECK((kCamera.project(T * (mapped.col(i) + same.col(i)).eval()) - px.col(i)).norm() < 1e-3);
    if (id != 27) CHECK(same.col(i).norm() < 1e-4);
  }
  CHECK(same(2, model.column_of(27)) < -0.002);  // into the face, onto its surface

  // A landmark seen 4 px to the right of the nose tip (the face's foremost point) lies on that ray,
  // on the flank of the nose: deeper than the tip.
  const int nose_tip = model.column_of(30);
  REQUIRE(nose_tip >= 0);
  Eigen::Matrix2Xd moved = px;
  moved(0, nose_tip) += 4.0;
  const Eigen::Matrix3Xd off = surface_landmark_offsets(candide, model, tau, 0.063, T, moved, kCamera, 0.015);
  const Eigen::Vector3d p_cam = T * (mapped.col(nose_tip) + off.col(nose_tip)).eval();
  CHECK(kCamera.project(p_cam).x() == Approx(px(0, nose_tip) + 4.0).margin(0.05));
  CHECK(kCamera.project(p_cam).y() == Approx(px(1, nose_tip)).margin(0.05));
  CHECK(std::abs(off(0, nose_tip)) > 0.5 * 4.0 * 0.8 / kCamera.fx);
  CHECK(off(2, nose_tip) < -1e-4);
  CHECK(off.col(nose_tip).norm() < 0.015);
  // The limit is on the in-plane part (what the picture saw), not on the depth the mesh gives.
  const double in_plane = off.col(nose_tip).head<2>().norm(), whole = off.col(nose_tip).norm();
  REQUIRE(whole > in_plane * 1.02);
  const Eigen::Matrix3Xd limited =
      surface_landmark_offsets(candide, model, tau, 0.063, T, moved, kCamera, 0.5 * (in_plane + whole));
  CHECK(limited.col(nose_tip).isApprox(off.col(nose_tip), 1e-6));
  const Eigen::Matrix3Xd refused = surface_landmark_offsets(candide, model, tau, 0.063, T, moved, kCamera, 0.9 * in_plane);
  CHECK(refused.col(nose_tip).norm() < 1e-6);

  // An eye corner seen 3 px outwards moves that eye's centre; the points are scaled back so that the
  // eye centres keep the interpupillary distance (the metric scale).
  const auto eye_distance = [&](const Eigen::Matrix3Xd& p) {
    Eigen::Vector3d right = Eigen::Vector3d::Zero(), left = Eigen::Vector3d::Zero();
    for (int id = 36; id < 42; ++id) right += p.col(model.column_of(id)) / 6.0;
    for (int id = 42; id < 48; ++id) left += p.col(model.column_of(id)) / 6.0;
    return (left - right).norm();
  };
  Eigen::Matrix2Xd wider = px;
  wider(0, model.column_of(45)) += 3.0;
  const Eigen::Matrix3Xd scaled = surface_landmark_offsets(candide, model, tau, 0.063, T, wider, kCamera, 0.015);
  CHECK(eye_distance(mapped + scaled) == Approx(eye_distance(mapped)).epsilon(1e-9));
  CHECK(scaled.col(model.column_of(45)).norm() > 0.5 * 3.0 * 0.8 / kCamera.fx);

  // A ray past the face keeps the mapped point.
  moved(0, nose_tip) += 400.0;
  const Eigen::Matrix3Xd missed = surface_landmark_offsets(candide, model, tau, 0.063, T, moved, kCamera, 0.015);
  CHECK(missed.col(nose_tip).norm() < 1e-6);
  CHECK_THROWS_AS(surface_landmark_offsets(candide, model, tau, 0.063, T, moved.leftCols(3), kCamera, 0.015),
                  std::invalid_argument);
}

TEST_CASE("face: person files keep the landmark offsets and refuse implausible ones") {
  const ScratchDir scratch("face_offsets");
  const std::filesystem::path& dir = scratch.path();
  PersonShape p{"bea", 0.062, Eigen::VectorXd::Constant(14, 0.1), 1.2, {}};
  p.landmark_offsets_m = Eigen::Matrix3Xd::Constant(3, 43, 0.002);
  p.landmark_offsets_m(2, 5) = -0.004;
  const auto file = person_shape_path(dir, "bea");
  save_person_shape(p, file);
  const PersonShape back = load_person_shape(file, 14);
  REQUIRE(back.landmark_offsets_m.cols() == 43);
  CHECK(back.landmark_offsets_m.isApprox(p.landmark_offsets_m, 1e-9));
  {
    std::ofstream out(file);
    out << R"({"name": "bea", "interpupillary_distance_mm": 62, "shape_params": [0,0,0,0,0,0,0,0,0,0,0,0,0,0],
               "landmark_offsets_mm": [[1, 2, 40]]})";
  }
  CHECK_THROWS_WITH(load_person_shape(file, 14), Catch::Contains("landmark_offsets_mm[0]"));
}
