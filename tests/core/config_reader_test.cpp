#include <catch2/catch.hpp>

#include "core/camera_config.hpp"
#include "core/config_reader.hpp"

using namespace labo;

namespace {
// The message a bad document gets when `read` consumes it.
template <typename F>
std::string error_of(const std::string& text, F read) {
  try {
    const ConfigDocument doc = ConfigDocument::parse(text, "test.json");
    read(doc.root());
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}
}  // namespace

TEST_CASE("config: invalid JSON names the file and the byte") {
  const auto msg = error_of("{\"a\": 1,,}", [](const ConfigReader&) {});
  CHECK_THAT(msg, Catch::Contains("test.json: invalid JSON at byte"));
}

TEST_CASE("config: a top level that is not an object is refused") {
  CHECK_THAT(error_of("[1, 2]", [](const ConfigReader&) {}), Catch::Contains("expected a JSON object at the top level, found array"));
}

TEST_CASE("config: a missing file is refused with its name") {
  CHECK_THROWS_WITH(ConfigDocument::load("/nonexistent/labo.json"),
                    Catch::Contains("/nonexistent/labo.json: cannot read the file"));
}

TEST_CASE("config: a missing required key names its path") {
  const auto msg = error_of("{\"a\": {}}", [](const ConfigReader& r) { r.object("a").number("b"); });
  CHECK(msg == "test.json: a.b: missing (required key)");
}

TEST_CASE("config: a wrong type names the value found and the expectation") {
  const auto msg = error_of("{\"a\": {\"b\": \"x\"}}", [](const ConfigReader& r) { r.object("a").number("b"); });
  CHECK(msg == "test.json: a.b: found \"x\" (string), expected a finite number");
}

TEST_CASE("config: a number out of range names the range") {
  const auto msg = error_of("{\"alpha\": 1.5}", [](const ConfigReader& r) { r.number("alpha", Range{0.0, 1.0, true}); });
  CHECK(msg == "test.json: alpha: found 1.5 (number), expected a number in (0, 1]");
  const auto neg = error_of("{\"w\": -2}", [](const ConfigReader& r) { r.number("w", Range::positive()); });
  CHECK(neg == "test.json: w: found -2 (integer), expected a number > 0");
}

TEST_CASE("config: integers refuse fractions and out-of-range values") {
  CHECK_THAT(error_of("{\"n\": 2.5}", [](const ConfigReader& r) { r.integer("n", 0, 10); }),
             Catch::Contains("n: found 2.5 (number), expected an integer in [0, 10]"));
  CHECK_THAT(error_of("{\"n\": 11}", [](const ConfigReader& r) { r.integer("n", 0, 10); }),
             Catch::Contains("n: found 11 (integer), expected an integer in [0, 10]"));
}

TEST_CASE("config: booleans, strings and choices are type checked") {
  CHECK_THAT(error_of("{\"b\": 1}", [](const ConfigReader& r) { r.boolean("b"); }), Catch::Contains("b: found 1 (integer), expected true or false"));
  CHECK_THAT(error_of("{\"s\": 3}", [](const ConfigReader& r) { r.string("s"); }), Catch::Contains("s: found 3 (integer), expected a string"));
  CHECK_THAT(error_of("{\"m\": \"fast\"}", [](const ConfigReader& r) { r.choice("m", {"ecc", "ic"}); }),
             Catch::Contains("m: found \"fast\" (string), expected one of \"ecc\" \"ic\""));
}

TEST_CASE("config: arrays check their length and every element") {
  CHECK_THAT(error_of("{\"d\": [1, 2]}", [](const ConfigReader& r) { r.numbers("d", 5); }),
             Catch::Contains("d: found [1,2] (array), expected an array of 5 numbers"));
  CHECK_THAT(error_of("{\"d\": [1, \"x\"]}", [](const ConfigReader& r) { r.numbers("d", 2); }),
             Catch::Contains("d[1]: found \"x\" (string), expected a finite number"));
  CHECK_THAT(error_of("{\"o\": [1]}", [](const ConfigReader& r) { r.objects("o"); }),
             Catch::Contains("o[0]: found 1 (integer), expected an object"));
}

TEST_CASE("config: unknown keys are errors that list the expected ones") {
  const auto msg = error_of("{\"alpha\": 0.8, \"alpah\": 0.7}", [](const ConfigReader& r) {
    r.number("alpha");
    r.finish();
  });
  CHECK(msg == "test.json: unknown key alpah (expected one of: alpha)");
}

TEST_CASE("config: optional keys fall back to their defaults and are still validated") {
  const ConfigDocument doc = ConfigDocument::parse("{\"a\": 2}", "t");
  const ConfigReader r = doc.root();
  CHECK(r.number_or("a", 1.0) == 2.0);
  CHECK(r.number_or("b", 1.0) == 1.0);
  CHECK(r.integer_or("c", 7) == 7);
  CHECK_NOTHROW(r.finish());
  CHECK_THROWS_WITH(r.number_or("a", 1.0, Range::closed(3, 4)), Catch::Contains("expected a number in [3, 4]"));
}

TEST_CASE("config: camera intrinsics are read and checked") {
  const ConfigDocument doc = ConfigDocument::parse(
      R"({"width": 640, "height": 360, "fx": 569.9, "fy": 568.0, "cx": 331.4, "cy": 135.9,
          "distortion": [-0.527, 0.274, 0.021, -0.006, 0.0]})",
      "cam.json");
  const CameraIntrinsics k = read_camera_intrinsics(doc.root());
  CHECK(k.fx == Approx(569.9));
  CHECK(k.k1 == Approx(-0.527));
  CHECK_THAT(error_of(R"({"width": 640, "height": 360, "fx": 0, "fy": 1, "cx": 1, "cy": 1})",
                      [](const ConfigReader& r) { read_camera_intrinsics(r); }),
             Catch::Contains("fx: found 0 (integer), expected a number > 0"));
  CHECK_THAT(error_of(R"({"width": 640, "height": 360, "fx": 1, "fy": 1, "cx": 700, "cy": 1})",
                      [](const ConfigReader& r) { read_camera_intrinsics(r); }),
             Catch::Contains("cx: found 700 (integer), expected a number in [0, 640]"));
  CHECK(k.calibration_error_px == 0.0);  // optional: a calibration taken as this unit's own
  const ConfigDocument with_error = ConfigDocument::parse(
      R"({"width": 640, "height": 360, "fx": 700, "fy": 700, "cx": 320, "cy": 180, "calibration_error_px": 6})", "cam.json");
  CHECK(read_camera_intrinsics(with_error.root()).calibration_error_px == 6.0);
  CHECK_THAT(error_of(R"({"width": 640, "height": 360, "fx": 1, "fy": 1, "cx": 1, "cy": 1, "calibration_error_px": -2})",
                      [](const ConfigReader& r) { read_camera_intrinsics(r); }),
             Catch::Contains("calibration_error_px: found -2 (integer), expected a number in [0, 50]"));
}
