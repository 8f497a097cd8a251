#include <catch2/catch.hpp>
#include <cmath>
#include <nlohmann/json.hpp>

#include "server/video/overlay_geometry.hpp"

using namespace labo;
using namespace labo::server;
using nlohmann::json;

TEST_CASE("web: the overlay geometry of a frame is JSON with the frame's stamp, every group and the HUD") {
  OverlayModel o;
  o.panel.corners = {{220, 100}, {420.25f, 100}, {420, 220}, {220, 220}};
  o.panel.axes = AxesPx{{320, 160}, {380, 160}, {320, 220}, {300, 140}};
  o.panel.measured_t = 9.5;
  o.face.points = {{10, 20}, {30, std::nanf("")}, {50, 60}};
  o.face.edges = {{0, 1}, {1, 2}};
  o.face.measured_t = 9.0;
  FlightTelemetry t;
  t.source = PoseSource::Homography;
  t.battery_percent = 87;
  t.altitude_m = 1.234;
  t.pose.yaw_rad = M_PI / 2;
  t.link_quality = 0.5;
  t.mission = "inspect";
  t.stage = "3 \"hold\"\n";
  OverlayGeometryWriter writer;
  const auto text = writer.write(o, t, {42, 1.7e12 + 0.25, CameraId::Front, 640, 360}, 1000.0);
  const json j = json::parse(*text, nullptr, false);
  REQUIRE_FALSE(j.is_discarded());
  CHECK(j["type"] == "overlay");
  CHECK(j["frame"] == 42);
  CHECK(j["capture_ms"].get<double>() == 1.7e12 + 0.25);
  CHECK(j["camera"] == "front");
  CHECK(j["width"] == 640);
  CHECK(j["source_colour"] == "#1060ff");
  CHECK(j["panel"]["corners"][1][0].get<double>() == Approx(420.2).margin(0.06));
  CHECK(j["panel"]["axes"]["x"] == json::array({380.0, 160.0}));
  CHECK(j["panel"]["measured_ms"].get<double>() == 1009500.0);
  CHECK(j["platform"].is_null());
  CHECK(j["face"]["points"][1][1].is_null());  // not finite: null, still valid JSON
  CHECK(j["face"]["edges"] == json::array({json::array({0, 1}), json::array({1, 2})}));
  CHECK(j["face"]["axes"].is_null());
  CHECK(j["hud"]["yaw_deg"].get<double>() == Approx(90.0));
  CHECK(j["hud"]["altitude_m"].get<double>() == Approx(1.23));
  CHECK(j["hud"]["stage"] == "3 \"hold\"\n");
}

TEST_CASE("web: overlay geometry is built into pooled buffers that are reused once released") {
  OverlayGeometryWriter writer;
  OverlayModel o;
  FlightTelemetry t;
  const std::string* first = nullptr;
  for (std::uint32_t n = 0; n < 100; ++n) {
    const auto text = writer.write(o, t, {n, 0, CameraId::Bottom, 640, 360}, 0);
    if (!first) first = text.get();
    CHECK(json::parse(*text)["camera"] == "bottom");
  }
  // Each message was released before the next: one buffer served them all.
  CHECK(writer.write(o, t, {0, 0, CameraId::Front, 640, 360}, 0).get() == first);
}
