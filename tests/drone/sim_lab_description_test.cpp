#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "core/config_reader.hpp"
#include "drone/lab/instrument_panels.hpp"
#include "drone/lab/lab_description.hpp"
#include "tests/support/scratch_dir.hpp"

using namespace labo;
using namespace labo::lab;
using labo::test::ScratchDir;
using nlohmann::json;

namespace {

json default_lab_json() {
  std::ifstream in(default_lab_path());
  json j = json::parse(in);
  // Absolute template paths, so the variants can live in a temporary folder.
  const auto dir = default_lab_path().parent_path();
  for (auto& i : j["instruments"]) i["template"] = (dir / i["template"].get<std::string>()).string();
  j["platform"]["template"] = (dir / j["platform"]["template"].get<std::string>()).string();
  return j;
}

std::filesystem::path write_variant(const json& j, const std::string& name) {
  static const ScratchDir dir("sim_lab");  // one per test process, removed at exit
  const auto path = dir / (name + ".json");
  std::ofstream(path) << j.dump(2);
  return path;
}

// Loads the variant and returns the error message ("" when it loaded).
std::string load_error(const json& j, const std::string& name) {
  try {
    load_lab_description(write_variant(j, name));
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("sim: the default lab loads with its instruments, platform and teacher") {
  const LabDescription lab = load_lab_description(default_lab_path());
  CHECK(lab.room.size().isApprox(Eigen::Vector3d(8, 6, 3)));
  CHECK(lab.instruments.size() >= 2);
  CHECK(lab.benches.size() >= 1);
  CHECK(lab.platform.thickness_m == Approx(0.10));
  CHECK(lab.surface_height(0.0, 0.0) == Approx(0.10));     // on the platform
  CHECK(lab.surface_height(1.0, 0.0) == Approx(0.0));      // floor
  CHECK(lab.surface_height(6.0, -2.0) == Approx(0.9));     // bench_east
  CHECK(lab.T_world_base.translation().isApprox(Eigen::Vector3d(0, 0, 0.10)));
  const InstrumentSpec* scope = lab.find_instrument("oscilloscope");
  REQUIRE(scope != nullptr);
  // The panel faces -x: a viewer at smaller x sees its left edge at larger y, its top higher up.
  const auto c = scope->corners_world();
  CHECK(c[0].y() > c[1].y());
  CHECK(c[0].z() > c[3].z());
  CHECK(scope->T_world_object.linear().col(2).isApprox(Eigen::Vector3d::UnitX()));
  // The platform's object z points down, its template top towards +x.
  CHECK(lab.platform.T_world_object.linear().col(2).isApprox(-Eigen::Vector3d::UnitZ()));
  CHECK(lab.platform.corners_world()[0].x() > lab.platform.corners_world()[3].x());
  CHECK(lab.floor_is_bare(3.0, -2.0));
  CHECK_FALSE(lab.floor_is_bare(1.0, 0.0));
}

TEST_CASE("sim: the committed instrument templates are what the generator draws") {
  const auto dir = default_lab_path().parent_path() / "instruments";
  const ScratchDir tmp("sim_textures");
  const auto written = write_instrument_templates(tmp.path());
  REQUIRE(written.size() == 4);
  for (const auto& p : written) {
    const auto committed = dir / p.filename();
    REQUIRE(std::filesystem::exists(committed));
    std::ifstream a(p, std::ios::binary), b(committed, std::ios::binary);
    const std::string sa((std::istreambuf_iterator<char>(a)), {}), sb((std::istreambuf_iterator<char>(b)), {});
    CHECK(sa == sb);
  }
}

TEST_CASE("sim: a lab file with bad content is refused naming the file, the key and the reason") {
  SECTION("overlapping benches") {
    json j = default_lab_json();
    j["benches"][1]["min"] = {5.0, 0.5, 0.0};
    j["benches"][1]["max"] = {6.0, 2.0, 0.9};
    const std::string e = load_error(j, "overlap");
    CHECK_THAT(e, Catch::Contains("overlap.json") && Catch::Contains("benches[1]") && Catch::Contains("overlaps 'bench_east'"));
  }
  SECTION("an instrument inside a bench") {
    json j = default_lab_json();
    j["instruments"][0]["centre"] = {6.0, -1.2, 0.8};
    CHECK_THAT(load_error(j, "sunk"), Catch::Contains("instruments[0]") && Catch::Contains("overlaps 'bench_east'"));
  }
  SECTION("a missing texture") {
    json j = default_lab_json();
    j["instruments"][1]["template"] = "/nonexistent/panel.png";
    CHECK_THAT(load_error(j, "missing"), Catch::Contains("instruments[1].template") && Catch::Contains("missing texture"));
  }
  SECTION("a texture whose aspect does not match the panel") {
    json j = default_lab_json();
    j["instruments"][0]["height_m"] = 0.35;
    CHECK_THAT(load_error(j, "aspect"), Catch::Contains("instruments[0].template") && Catch::Contains("aspect"));
  }
  SECTION("a camera outside the room") {
    json j = default_lab_json();
    j["cameras"][0]["position"] = {-2.0, 0.0, 1.0};
    CHECK_THAT(load_error(j, "camera"), Catch::Contains("cameras[0].position") && Catch::Contains("outside the room"));
  }
  SECTION("non-positive sizes") {
    json j = default_lab_json();
    j["instruments"][2]["width_m"] = 0.0;
    CHECK_THAT(load_error(j, "width"), Catch::Contains("instruments[2].width_m") && Catch::Contains("> 0"));
    json k = default_lab_json();
    k["benches"][0]["max"] = {5.7, 1.2, 0.9};
    CHECK_THAT(load_error(k, "flat"), Catch::Contains("benches[0].max") && Catch::Contains("non-positive size"));
    json r = default_lab_json();
    r["room"]["max"] = {6.5, -3.0, 3.0};
    CHECK_THAT(load_error(r, "room"), Catch::Contains("room.max") && Catch::Contains("non-positive size"));
  }
  SECTION("a teacher path through a wall") {
    json j = default_lab_json();
    j["teacher"]["waypoints"][1] = {{"x", 7.5}, {"y", -2.0}};
    CHECK_THAT(load_error(j, "wall"), Catch::Contains("teacher.waypoints[0]") && Catch::Contains("passes through a wall"));
  }
  SECTION("a teacher path through a bench") {
    json j = default_lab_json();
    j["teacher"]["waypoints"][2] = {{"x", 4.6}, {"y", 2.6}};
    CHECK_THAT(load_error(j, "bench"), Catch::Contains("teacher.waypoints[") && Catch::Contains("walks through 'bench_north'"));
  }
  SECTION("unknown keys and duplicate ids") {
    json j = default_lab_json();
    j["instruments"][0]["colour"] = "red";
    CHECK_THAT(load_error(j, "unknown"), Catch::Contains("instruments[0].colour"));
    json k = default_lab_json();
    k["instruments"][1]["id"] = "oscilloscope";
    CHECK_THAT(load_error(k, "dup"), Catch::Contains("duplicate id 'oscilloscope'"));
  }
}
