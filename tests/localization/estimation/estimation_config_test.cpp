#include <catch2/catch.hpp>
#include <utility>
#include <vector>

#include "core/config_reader.hpp"
#include "localization/estimation/estimation_config.hpp"

using namespace labo;
using namespace labo::estimation;

TEST_CASE("estimation: config reads delays in ms and model constants, refuses bad values") {
  const ConfigDocument doc = ConfigDocument::parse(
      R"({"video_delay_ms": 80, "navdata_delay_ms": 30, "control_delay_ms": 120,
          "model": {"tilt_max_deg": 15, "drag_per_s": 0.7}})",
      "test.json");
  const estimation::EstimatorConfig c = estimation::read_estimation_config(doc.root());
  CHECK(c.video_delay_s == Approx(0.080));
  CHECK(c.navdata_delay_s == Approx(0.030));
  CHECK(c.control_delay_s == Approx(0.120));
  CHECK(c.model.tilt_max_rad == Approx(15.0 * 3.14159265358979 / 180.0));
  CHECK(c.model.drag_per_s == Approx(0.7));

  const ConfigDocument bad = ConfigDocument::parse(R"({"video_delay_ms": -5})", "bad.json");
  CHECK_THROWS_WITH(estimation::read_estimation_config(bad.root()), Catch::Contains("video_delay_ms"));
  const ConfigDocument unknown = ConfigDocument::parse(R"({"model": {"tilt_max": 12}})", "unknown.json");
  CHECK_THROWS_WITH(estimation::read_estimation_config(unknown.root()), Catch::Contains("tilt_max"));
  const ConfigDocument order = ConfigDocument::parse(R"({"scale_interval_min_s": 3, "scale_interval_max_s": 2})", "o.json");
  CHECK_THROWS_WITH(estimation::read_estimation_config(order.root()), Catch::Contains("scale_interval_max_s"));
}

TEST_CASE("estimation: config reads the firmware's command hold and hover stop, refuses what no firmware has") {
  struct Key {
    const char* name;
    Seconds estimation::EstimatorConfig::*field;
    const char* good;  // the document, and the value it gives
    double value;
    std::vector<const char*> bad;
  };
  const std::vector<Key> keys = {
      {"firmware_command_hold_s", &estimation::EstimatorConfig::firmware_command_hold_s, R"({"firmware_command_hold_s": 15})", 15.0,
       {R"({"firmware_command_hold_s": -1})", R"({"firmware_command_hold_s": 31})", R"({"firmware_command_hold_s": "2 s"})"}},
      {"firmware_hover_stop_s", &estimation::EstimatorConfig::firmware_hover_stop_s, R"({"firmware_hover_stop_s": 0.6})", 0.6,
       {R"({"firmware_hover_stop_s": 0})", R"({"firmware_hover_stop_s": 11})", R"({"firmware_hover_stop_s": "1 s"})"}}};
  for (const Key& k : keys) {
    INFO(k.name);
    const estimation::EstimatorConfig c = estimation::read_estimation_config(ConfigDocument::parse(k.good, "tello.json").root());
    CHECK(c.*k.field == Approx(k.value));
    for (const char* text : k.bad) {
      const ConfigDocument bad = ConfigDocument::parse(text, "bad.json");
      CHECK_THROWS_WITH(estimation::read_estimation_config(bad.root()), Catch::Contains(k.name));
    }
  }
}

TEST_CASE("estimation: config reads the velocity dropout detector, refuses bad values") {
  const ConfigDocument doc = ConfigDocument::parse(
      R"({"velocity_dropout": {"enabled": false, "window_s": 0.5, "onset_mps": 0.15, "confirm_packets": 3}})", "test.json");
  const estimation::EstimatorConfig c = estimation::read_estimation_config(doc.root());
  CHECK_FALSE(c.velocity_dropout.enabled);
  CHECK(c.velocity_dropout.window_s == Approx(0.5));
  CHECK(c.velocity_dropout.onset_mps == Approx(0.15));
  CHECK(c.velocity_dropout.confirm_packets == 3);
  CHECK(c.velocity_dropout.agree_mps == Approx(estimation::VelocityDropoutSettings{}.agree_mps));

  const auto refuses = [](const char* json, const char* key) {
    const ConfigDocument bad = ConfigDocument::parse(json, "bad.json");
    CHECK_THROWS_WITH(estimation::read_estimation_config(bad.root()), Catch::Contains(key));
  };
  refuses(R"({"velocity_dropout": {"onset_mps": -0.1}})", "onset_mps");
  refuses(R"({"velocity_dropout": {"onset_ratio": 1.5}})", "onset_ratio");
  refuses(R"({"velocity_dropout": {"window_s": 0.2, "average_s": 0.3}})", "average_s");
  refuses(R"({"velocity_dropout": {"confirm_packets": 0}})", "confirm_packets");
  refuses(R"({"velocity_dropout": {"window": 0.4}})", "window");
}

TEST_CASE("estimation: config reads the dead-reckoning drift bound, refuses bad values") {
  const ConfigDocument doc = ConfigDocument::parse(
      R"({"drift_bound": {"velocity_bias_mps": 0.05, "velocity_scale": 0.1, "dropout_mps": 0.2}})", "test.json");
  const estimation::EstimatorConfig c = estimation::read_estimation_config(doc.root());
  CHECK(c.drift_bound.velocity_bias_mps == Approx(0.05));
  CHECK(c.drift_bound.velocity_scale == Approx(0.1));
  CHECK(c.drift_bound.dropout_mps == Approx(0.2));
  for (const auto& [json, key] : {std::pair{R"({"drift_bound": {"velocity_bias_mps": -0.01}})", "velocity_bias_mps"},
                                  std::pair{R"({"drift_bound": {"velocity_scale": 2}})", "velocity_scale"},
                                  std::pair{R"({"drift_bound": {"dropout_mps": "fast"}})", "dropout_mps"},
                                  std::pair{R"({"drift_bound": {"bias": 0.1}})", "bias"}}) {
    const ConfigDocument bad = ConfigDocument::parse(json, "bad.json");
    CHECK_THROWS_WITH(estimation::read_estimation_config(bad.root()), Catch::Contains(key));
  }
}

TEST_CASE("estimation: a drone's own section is read over the estimation section") {
  const ConfigDocument doc = ConfigDocument::parse(R"({"navdata_delay_ms": 30, "scale_sigma_metric_m": 0.03})", "e.json");
  const EstimatorConfig base = read_estimation_config(doc.root());
  const ConfigDocument over = ConfigDocument::parse(R"({"scale_max_navdata_gap_s": 0.15, "scale_weight_xy": 0.5})", "t.json");
  const EstimatorConfig c = read_estimation_config(over.root(), base);
  CHECK(c.navdata_delay_s == Approx(0.030));        // kept from the base
  CHECK(c.scale.sigma_metric_m == Approx(0.03));    // kept from the base
  CHECK(c.scale_max_navdata_gap_s == Approx(0.15));  // replaced
  CHECK(c.scale_weight_xy == Approx(0.5));
  CHECK(base.scale_max_navdata_gap_s == Approx(0.1));
  const ConfigDocument bad = ConfigDocument::parse(R"({"scale_max_navdata_gap_s": 0})", "bad.json");
  CHECK_THROWS_WITH(read_estimation_config(bad.root(), base), Catch::Contains("scale_max_navdata_gap_s"));
}
