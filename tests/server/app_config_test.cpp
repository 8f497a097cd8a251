#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>

#include "server/app_config.hpp"
#include "tests/support/scratch_dir.hpp"

using namespace labo;
using namespace labo::tello;
using namespace labo::server;
using labo::test::ScratchDir;

TEST_CASE("app config: the shipped default.json loads with the paper's thresholds") {
  const AppConfig c = load_app_config(default_config_path());
  CHECK(c.vision.template_correlation_alpha == Approx(0.8));
  CHECK(c.vision.angle_jump_beta_rad == Approx(15.0 * 3.14159265358979 / 180.0));
  CHECK(c.vision.distance_jump_m == Approx(0.30));
  CHECK(c.vision.ultrasound_step_gamma_m == Approx(0.10));
  CHECK(c.vision.sift_min_inliers >= 10);
  CHECK(c.vision.sift_min_inliers <= 30);
  CHECK(c.cameras.front.fx == Approx(569.9));
  CHECK(c.cameras.bottom.cy == Approx(218.7));
  CHECK(c.server.port == 8080);
  // A Tello's estimator: the tello section's "estimation" over the estimation section.
  CHECK(c.estimation.scale_max_navdata_gap_s == Approx(0.1));
  CHECK(c.tello_estimation.scale_max_navdata_gap_s == Approx(0.15));
  CHECK(c.tello_estimation.navdata_delay_s == Approx(c.estimation.navdata_delay_s));
}

TEST_CASE("app config: tello config: the cameras' defaults and the downward camera") {
  // The defaults in code and the shipped file agree: the Tello's front camera from its specification
  // with the allowance of an uncalibrated lens (9 px at the corner), the Tello EDU's downward camera
  // 320x240 with the AR.Drone bottom camera's field of view (4 px), asked for and answered.
  for (const TelloConfig& t : {TelloConfig{}, load_app_config(default_config_path()).tello}) {
    CHECK(t.camera.width == 960);
    CHECK(t.camera.fx == Approx(682.96).margin(0.01));
    CHECK(t.camera.calibration_error_px == Approx(9.0));
    CHECK(t.bottom_camera.width == 320);
    CHECK(t.bottom_camera.height == 240);
    CHECK(t.bottom_camera.fx == Approx(350.0));
    CHECK(t.bottom_camera.calibration_error_px == Approx(4.0));
    CHECK(t.link.downvision);
    CHECK(t.emulator.firmware.downvision);
  }
  const CamerasConfig cameras = tello_cameras(TelloConfig{}, load_app_config(default_config_path()).cameras);
  CHECK(cameras.front.width == 960);
  CHECK(cameras.bottom.width == 320);
}

TEST_CASE("app config: bad sections are refused with the key path") {
  auto error_of = [](const std::string& text) -> std::string {
    try {
      const ConfigDocument doc = ConfigDocument::parse(text, "bad.json");
      read_app_config(doc.root(), ".");
    } catch (const ConfigError& e) {
      return e.what();
    }
    return "";
  };
  CHECK(error_of(R"({"vision": {"sift_min_inliers": 5}})") ==
        "bad.json: vision.sift_min_inliers: found 5 (integer), expected an integer in [10, 30]");
  CHECK(error_of(R"({"vision": {"sift_switch_distance_m": 4}})") ==
        "bad.json: vision.sift_switch_distance_m: found 4 (integer), expected a number in [1, 3]");
  CHECK(error_of(R"({"vision": {"template_correlation_alpha": 0}})") ==
        "bad.json: vision.template_correlation_alpha: found 0 (integer), expected a number in (0, 1]");
  CHECK(error_of(R"({"server": {"port": 0}})") == "bad.json: server.port: found 0 (integer), expected an integer in [1, 65535]");
  CHECK_THAT(error_of(R"({"servre": {}})"), Catch::Contains("bad.json: unknown key servre"));
  CHECK_THAT(error_of(R"({"log_level": "loud"})"), Catch::Contains("log_level: found \"loud\""));
  CHECK_THAT(error_of(R"({"cameras": {"front": {}}})"), Catch::Contains("cameras.front.width: missing"));
  CHECK_THAT(error_of(R"({"tello": {"estimation": 3}})"), Catch::Contains("tello.estimation"));
  // Frames are told apart by their size: the downward camera's is 320x240, and only its.
  CHECK_THAT(error_of(R"({"tello": {"bottom_camera": {"width": 640, "height": 480, "fx": 500, "fy": 500, "cx": 320, "cy": 240}}})"),
             Catch::Contains("tello.bottom_camera: must be 320x240, the downward camera's stream (got 640x480)"));
  CHECK_THAT(error_of(R"({"tello": {"camera": {"width": 320, "height": 240, "fx": 300, "fy": 300, "cx": 160, "cy": 120}}})"),
             Catch::Contains("tello.camera: must not be 320x240"));
  CHECK_THAT(error_of(R"({"tello": {"link": {"downvision": 1}}})"), Catch::Contains("tello.link.downvision"));
  CHECK_THAT(error_of(R"({"tello": {"estimation": {"scale_weight_z": -1}}})"), Catch::Contains("tello.estimation.scale_weight_z"));
}

TEST_CASE("app config: the lab description it names is loaded and validated") {
  const AppConfig c = load_app_config(default_config_path());
  CHECK(c.lab_file == default_config_path().parent_path() / "lab.json");
  REQUIRE(c.lab.instruments.size() == 3);
  CHECK(c.lab.find_instrument("oscilloscope"));

  const ScratchDir scratch("app_config_lab");
  const std::filesystem::path& dir = scratch.path();
  auto error_of = [&](const std::string& text) -> std::string {
    try {
      const ConfigDocument doc = ConfigDocument::parse(text, "bad.json");
      read_app_config(doc.root(), dir);
    } catch (const ConfigError& e) {
      return e.what();
    }
    return "";
  };
  CHECK_THAT(error_of(R"({"lab": "missing_lab.json"})"),
             Catch::Contains("bad.json: lab: no lab description at ") && Catch::Contains("missing_lab.json"));
  // A lab file with an error is refused with the lab file's name and key path.
  std::ofstream(dir / "broken_lab.json") << R"({"room": {"min": [0, 0, 0], "max": [1, 1, 1]}})";
  CHECK_THAT(error_of(R"({"lab": "broken_lab.json"})"), Catch::Contains("broken_lab.json") && Catch::Contains("room"));
}
