#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>

#include "core/candide3.hpp"
#include "tests/support/scratch_dir.hpp"

using namespace labo;
using labo::test::ScratchDir;

TEST_CASE("candide3: the shipped model has the published counts and axes") {
  const Candide3Model m = Candide3Model::load(Candide3Model::default_path());
  CHECK(m.vertices().size() == 113);
  CHECK(m.triangles().size() == 184);
  CHECK(m.animation_units().size() == 65);
  CHECK(m.shape_units().size() == 14);
  CHECK(m.shape_units()[0].name == "Head height");
  CHECK(m.vertices()[5].z() == Approx(0.21).margin(0.02));  // nose tip points out of the face (+z)
  CHECK(m.vertices()[21].x() > 0);                          // v21, left eyelid: +x is the subject's left
}

TEST_CASE("candide3: shape and animation parameters move the vertices they name") {
  const Candide3Model m = Candide3Model::load(Candide3Model::default_path());
  const std::vector<double> shape{0.5};  // head height
  const auto v = m.deformed(shape);
  CHECK(v[0].y() == Approx(m.vertices()[0].y() + 0.1));
  CHECK(v[10].y() == Approx(m.vertices()[10].y() - 0.1));
  CHECK(v[5] == m.vertices()[5]);
  const std::vector<double> too_many(15, 0.0);
  CHECK_THROWS_WITH(m.deformed(too_many), Catch::Contains("15 shape / 0 animation parameters given, the model has 14 / 65"));
}

TEST_CASE("candide3: the 68-landmark mapping covers the rigid points and the eyes are level") {
  const Candide3Model m = Candide3Model::load(Candide3Model::default_path());
  const Ibug68Mapping map = load_ibug68_mapping(default_ibug68_mapping_path());
  int mapped = 0;
  for (const auto& l : map) mapped += l.kind != LandmarkVertexMap::Kind::None;
  CHECK(mapped >= 60);
  const Eigen::Vector3d right_eye_outer = landmark_point(map[36], m.vertices());
  const Eigen::Vector3d left_eye_outer = landmark_point(map[45], m.vertices());
  CHECK(right_eye_outer.x() < 0);  // the subject's right is -x
  CHECK(left_eye_outer.x() == Approx(-right_eye_outer.x()).margin(1e-6));
  CHECK(left_eye_outer.y() == Approx(right_eye_outer.y()).margin(1e-6));
}

TEST_CASE("candide3: damaged files are refused with the line and reason") {
  const ScratchDir scratch("candide3");
  const std::filesystem::path& dir = scratch.path();
  const auto wfm = dir / "bad.wfm";
  std::ofstream(wfm) << "# VERTEX LIST:\n2\n0 0 0\n1 1\n";
  CHECK_THROWS_WITH(Candide3Model::load(wfm), Catch::Contains("bad.wfm:4: expected 3 numbers, found '1 1'"));
  std::ofstream(wfm) << "# VERTEX LIST:\n1\n0 0 0\n# FACE LIST:\n1\n0 0 7\n";
  CHECK_THROWS_WITH(Candide3Model::load(wfm), Catch::Contains("triangle vertex 7 out of range"));
  CHECK_THROWS_WITH(Candide3Model::load(dir / "missing.wfm"), Catch::Contains("cannot read the CANDIDE-3 model file"));
  const auto csv = dir / "bad.csv";
  std::ofstream(csv) << "dlib_idx,vertices,weights,kind\n0,500,1.0,direct\n";
  CHECK_THROWS_WITH(load_ibug68_mapping(csv), Catch::Contains("bad.csv:2: vertex 500 out of range"));
  std::ofstream(csv) << "0,1,1.0,direct\n";
  CHECK_THROWS_WITH(load_ibug68_mapping(csv), Catch::Contains("landmark 1 is missing"));
}
