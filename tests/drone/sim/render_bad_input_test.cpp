#include <catch2/catch.hpp>

#include "drone/sim/texture_map.hpp"
#include "drone/sim/texture_procedural.hpp"
#include "render_fixtures.hpp"

using namespace labo;
using namespace labo::lab;
using namespace labo::sim;
using namespace labo::test;
using Catch::Matchers::Contains;

TEST_CASE("render: a missing or undecodable template image is refused naming the file") {
  LabDescription lab = load_lab_description(default_lab_path());
  lab.instruments.front().template_path = "/nonexistent/panel.png";
  CHECK_THROWS_WITH(LabRenderer(lab, ardrone_cameras(), std::nullopt, 1),
                    Contains("/nonexistent/panel.png") && Contains("no such file") && Contains("oscilloscope.panel"));
  lab = load_lab_description(default_lab_path());
  lab.platform.template_path = default_lab_path();  // a JSON file, not an image
  CHECK_THROWS_WITH(LabRenderer(lab, ardrone_cameras(), std::nullopt, 1), Contains("not a decodable image"));
}

TEST_CASE("render: bad camera intrinsics and an uninvertible lens are refused") {
  const LabDescription lab = load_lab_description(default_lab_path());
  CamerasConfig cams = ardrone_cameras();
  cams.front.fx = 0;
  CHECK_THROWS_WITH(LabRenderer(lab, cams, std::nullopt, 1), Contains("cameras.front") && Contains("focal"));
  cams = ardrone_cameras();
  cams.bottom.k1 = -3.0;  // folds the image over itself
  CHECK_THROWS_WITH(LabRenderer(lab, cams, std::nullopt, 1), Contains("cannot be inverted"));
}

TEST_CASE("render: a malformed head model is refused with what is wrong") {
  const LabDescription lab = load_lab_description(default_lab_path());
  TexturedHeadModel head;
  head.vertices_face_m = {{0, 0, 0}, {0.05, 0, 0}, {0, 0.05, 0}};
  head.triangles = {{0, 1, 2}};
  head.texture_px = {{0, 0}, {10, 0}, {0, 10}};
  head.texture_bgr = cv::Mat(16, 16, CV_8UC3, cv::Scalar(100, 120, 140));
  CHECK_NOTHROW(LabRenderer(lab, ardrone_cameras(), head, 1));
  TexturedHeadModel bad = head;
  bad.texture_px.pop_back();
  CHECK_THROWS_WITH(LabRenderer(lab, ardrone_cameras(), bad, 1), Contains("2 texture coordinates for 3 vertices"));
  bad = head;
  bad.triangles = {{0, 1, 3}};
  CHECK_THROWS_WITH(LabRenderer(lab, ardrone_cameras(), bad, 1), Contains("triangle index 3"));
  bad = head;
  bad.vertices_face_m[1] = {5.0, 0, 0};
  CHECK_THROWS_WITH(LabRenderer(lab, ardrone_cameras(), bad, 1), Contains("metres"));
  bad = head;
  bad.texture_bgr = cv::Mat(16, 16, CV_32FC3);
  CHECK_THROWS_WITH(LabRenderer(lab, ardrone_cameras(), bad, 1), Contains("8-bit BGR"));
}

TEST_CASE("render: textures refuse empty images and oversize surfaces") {
  CHECK_THROWS_AS(TextureMap(cv::Mat()), std::invalid_argument);
  CHECK_THROWS_AS(TextureMap(cv::Mat(4, 4, CV_16UC1)), std::invalid_argument);
  SurfaceTextureRequest q;
  q.width_m = 100;  // 20000 texels
  CHECK_THROWS_WITH(draw_surface_texture(q), Contains("4096"));
  q.width_m = -1;
  CHECK_THROWS_WITH(draw_surface_texture(q), Contains("positive"));
}
