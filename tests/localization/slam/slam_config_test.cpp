#include <catch2/catch.hpp>

#include "localization/slam/slam_config.hpp"

using namespace labo;

TEST_CASE("slam: config section is read, range-checked and refuses unknown keys") {
  auto read = [](const std::string& text) {
    const ConfigDocument doc = ConfigDocument::parse(text, "test.json");
    return slam::read_slam_settings(doc.root());
  };
  const slam::SlamSettings s = read(R"({"mapping": "synchronous", "max_features": 800, "quality_good": 0.4})");
  CHECK(s.mapping_mode == slam::MappingMode::Synchronous);
  CHECK(s.max_features == 800);
  CHECK(s.quality_good == Approx(0.4));
  CHECK(read("{}").mapping_mode == slam::MappingMode::Threaded);
  CHECK_THROWS_WITH(read(R"({"mapping": "sometimes"})"), Catch::Contains("mapping"));
  CHECK_THROWS_WITH(read(R"({"max_features": 10})"), Catch::Contains("max_features"));
  CHECK(read(R"({"max_points_searched": 1200})").max_points_searched == 1200);
  CHECK(read(R"({"keyframe_min_points_dodgy": 0})").keyframe_min_points_dodgy == 0);
  CHECK(read(R"({"keyframe_overlap_ratio": 0.7})").keyframe_overlap_ratio == Approx(0.7));
  CHECK(read("{}").keyframe_overlap_ratio == Approx(0.55));
  CHECK_THROWS_WITH(read(R"({"keyframe_overlap_ratio": 1.2})"), Catch::Contains("keyframe_overlap_ratio"));
  CHECK_THROWS_WITH(read(R"({"keyframe_min_points_dodgy": -1})"), Catch::Contains("keyframe_min_points_dodgy"));
  CHECK_THROWS_WITH(read(R"({"max_points_searched": 10})"), Catch::Contains("max_points_searched"));
  CHECK_THROWS_WITH(read(R"({"quality_good": 0.1, "quality_lost": 0.2})"), Catch::Contains("quality_lost"));
  CHECK_THROWS_WITH(read(R"({"typo": 1})"), Catch::Contains("typo"));
  const slam::SlamSettings loops = read(R"({"loop_closure": false, "loop_min_gap_s": 30, "global_ba_fixed_keyframes": 1})");
  CHECK_FALSE(loops.loop_closure);
  CHECK(loops.loop_min_gap_s == Approx(30));
  CHECK(loops.global_ba_fixed_keyframes == 1);
  CHECK(read("{}").loop_closure);
  CHECK_THROWS_WITH(read(R"({"loop_min_gap_s": 0})"), Catch::Contains("loop_min_gap_s"));
  CHECK_THROWS_WITH(read(R"({"global_ba_fixed_keyframes": 0})"), Catch::Contains("global_ba_fixed_keyframes"));
  const slam::SlamSettings ba = read(R"({"global_ba_every": 5, "local_ba_keyframes": 8})");
  CHECK(ba.global_ba_every == 5);
  CHECK(ba.local_ba_keyframes == 8);
  CHECK(read("{}").local_ba_iterations == 10);
  CHECK(read("{}").global_ba_iterations == 10);
  const slam::SlamSettings iterations = read(R"({"local_ba_iterations": 20, "global_ba_iterations": 25})");
  CHECK(iterations.local_ba_iterations == 20);
  CHECK(iterations.global_ba_iterations == 25);
  CHECK_THROWS_WITH(read(R"({"local_ba_iterations": 0})"), Catch::Contains("local_ba_iterations"));
  CHECK_THROWS_WITH(read(R"({"global_ba_iterations": 500})"), Catch::Contains("global_ba_iterations"));
  CHECK_THROWS_WITH(read(R"({"global_ba_every": 0})"), Catch::Contains("global_ba_every"));
  CHECK_THROWS_WITH(read(R"({"local_ba_keyframes": 1})"), Catch::Contains("local_ba_keyframes"));
  const slam::SlamSettings init = read(R"({"init_min_parallax_deg": 3, "init_min_parallax_px": 40})");
  CHECK(init.init_min_parallax_deg == Approx(3));
  CHECK(init.init_min_parallax_px == Approx(40));
  CHECK(read("{}").init_min_parallax_deg == Approx(1.0));
  CHECK_THROWS_WITH(read(R"({"init_min_parallax_deg": 0})"), Catch::Contains("init_min_parallax_deg"));
  CHECK_THROWS_WITH(read(R"({"init_min_parallax_px": 500})"), Catch::Contains("init_min_parallax_px"));
  CHECK(read(R"({"patch_refinement": true})").patch_refinement);
  CHECK_FALSE(read("{}").patch_refinement);
  CHECK_THROWS_WITH(read(R"({"patch_refinement": 1})"), Catch::Contains("patch_refinement"));
  CHECK(read("{}").new_point_clearance_px == Approx(0.0));
  CHECK(read(R"({"new_point_clearance_px": 1.5})").new_point_clearance_px == Approx(1.5));
  CHECK_THROWS_WITH(read(R"({"new_point_clearance_px": -1})"), Catch::Contains("new_point_clearance_px"));
  CHECK_THROWS_WITH(read(R"({"new_point_clearance_px": "wide"})"), Catch::Contains("new_point_clearance_px"));
  CHECK(read("{}").gravity_sigma_deg == Approx(0.0));
  CHECK(read("{}").gravity_in_tracking);
  const slam::SlamSettings gravity = read(R"({"gravity_sigma_deg": 0.5, "gravity_in_tracking": false})");
  CHECK(gravity.gravity_sigma_deg == Approx(0.5));
  CHECK_FALSE(gravity.gravity_in_tracking);
  CHECK_THROWS_WITH(read(R"({"gravity_sigma_deg": -0.1})"), Catch::Contains("gravity_sigma_deg"));
  CHECK_THROWS_WITH(read(R"({"gravity_sigma_deg": 20})"), Catch::Contains("gravity_sigma_deg"));
}
