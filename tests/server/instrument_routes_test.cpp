// The admin's instruments over REST: an upload's template strength measured and a weak one refused
// with 422, placed in the upload or later (PUT .../placement), each refused input with its status,
// and the flight software given the placed instrument (ScriptedFlight records it).
#include <catch2/catch.hpp>
#include <opencv2/imgcodecs.hpp>
#include <numbers>
#include <opencv2/imgproc.hpp>

#include "server/api/instrument_placement.hpp"
#include "server/api/instrument_store.hpp"
#include "server/auth/password_hash.hpp"
#include "tests/server/support/server_fixture.hpp"
#include "tests/server/support/test_clients.hpp"

using namespace labo;
using namespace labo::lab;
using namespace labo::server;
using namespace labo::server::test;
using nlohmann::json;
using http::verb;

namespace {

// A panel's photo: rectangles of every grey over a light face, `w` x `h` pixels.
std::string panel_png_base64(int w, int h, int rectangles = 500) {
  cv::Mat img(h, w, CV_8UC3, cv::Scalar(200, 200, 200));
  cv::RNG rng(11);
  for (int i = 0; i < rectangles; ++i)
    cv::rectangle(img, cv::Rect(rng.uniform(0, w - 20), rng.uniform(0, h - 20), rng.uniform(5, 20), rng.uniform(5, 20)),
                  cv::Scalar(rng.uniform(0, 255), rng.uniform(0, 255), rng.uniform(0, 255)), cv::FILLED);
  std::vector<std::uint8_t> png;
  cv::imencode(".png", img, png);
  return base64_encode(png);
}

json upload(const std::string& id) {
  return {{"id", id}, {"name", "Multimeter"}, {"width_m", 0.2}, {"height_m", 0.1}, {"image_base64", panel_png_base64(400, 200)}};
}

}  // namespace

TEST_CASE("web: an uploaded instrument is stored unplaced, then placed live and handed to the flight software") {
  ServerFixture f;
  const std::string root = login_cookie(f.port, "root", "root-pw");
  const std::string alice = login_cookie(f.port, "alice", "alice-pw");
  const HttpResult created = http_call(f.port, verb::post, "/api/instruments", upload("dmm").dump(), root);
  REQUIRE(created.status == 201);
  CHECK(created.json()["placed"] == false);
  CHECK(created.json()["inspectable"] == false);
  CHECK(created.json()["strength"]["sift_keypoints"].get<int>() >= planar::TemplateStrengthLimits{}.min_sift_keypoints);
  CHECK(f.flight.placed.empty());

  const auto place = [&](const json& body, const std::string& who, const std::string& id = "dmm") {
    return http_call(f.port, verb::put, "/api/instruments/" + id + "/placement", body.dump(), who);
  };
  const json where{{"position_m", {5.6, -0.8, 1.05}}, {"yaw_deg", 180}};
  CHECK(place(where, alice).status == 403);
  CHECK(place(where, root, "nothing").status == 404);
  CHECK(place(where, root, "oscilloscope").status == 409);  // the lab file's
  CHECK(place(where, root, "Bad Id").status == 400);
  CHECK(place({{"position_m", {1, 2}}, {"yaw_deg", 0}}, root).status == 400);
  CHECK(place({{"position_m", {1, 2, 1}}}, root).status == 400);
  CHECK(place({{"position_m", {1, 2, 1}}, {"yaw_deg", 0}, {"colour", "red"}}, root).status == 400);
  CHECK(place(json::object(), root).status == 400);
  // Wrong types: each refusal names the field and what it expects.
  const auto refusal = [&](const json& body) {
    const HttpResult r = place(body, root);
    CHECK(r.status == 400);
    return r.json()["error"].get<std::string>();
  };
  CHECK(refusal({{"position_m", "by the window"}, {"yaw_deg", 0}}).find("'position_m' must be [x, y, z] in metres") != std::string::npos);
  CHECK(refusal({{"position_m", {"5.6", -0.8, 1.05}}, {"yaw_deg", 0}}).find("'position_m' values must be numbers") != std::string::npos);
  CHECK(refusal({{"position_m", {5.6, -0.8, 1.05}}, {"yaw_deg", "west"}}).find("'yaw_deg'") != std::string::npos);
  CHECK(refusal({{"position_m", {5.6, -0.8, 1.05}}, {"yaw_deg", 270}}).find("[-180, 180]") != std::string::npos);
  CHECK(refusal({{"position_m", {5.6, -0.8, 1e9}}, {"yaw_deg", 180}}).find("within 100 m") != std::string::npos);
  CHECK(place(where, root, "nothing").json()["error"] == "no uploaded instrument 'nothing'");
  CHECK(http_call(f.port, verb::put, "/api/instruments/dmm/placement", "[1, 2]", root).status == 400);
  // Outside the room, into the east bench (its top at 0.9 m), onto the platform: 422, saying where.
  const HttpResult outside = place({{"position_m", {7.5, 0, 1}}, {"yaw_deg", 180}}, root);
  CHECK(outside.status == 422);
  CHECK(outside.json()["error"].get<std::string>().find("not inside the room") != std::string::npos);
  const HttpResult in_bench = place({{"position_m", {6.0, -0.8, 0.85}}, {"yaw_deg", 180}}, root);
  CHECK(in_bench.status == 422);
  CHECK(in_bench.json()["error"].get<std::string>().find("bench 'bench_east'") != std::string::npos);
  CHECK(place({{"position_m", {0, 0, 0.1}}, {"yaw_deg", 0}}, root).status == 422);
  CHECK(f.flight.placed.empty());

  // On the bench's top, facing the room (-x): placed, and the flight software has it.
  const HttpResult placed = place(where, root);
  REQUIRE(placed.status == 200);
  CHECK(placed.json()["inspectable"] == true);
  REQUIRE(f.flight.placed.size() == 1);
  const InstrumentSpec& spec = f.flight.placed[0];
  CHECK(spec.T_world_object.translation().isApprox(Eigen::Vector3d(5.6, -0.8, 1.05)));
  CHECK(spec.T_world_object.linear().col(2).isApprox(Eigen::Vector3d(1, 0, 0), 1e-9));  // z into the panel: it faces -x
  CHECK(std::filesystem::exists(spec.template_path));
  CHECK(place(where, root).status == 409);  // placed already
  const json list = http_call(f.port, verb::get, "/api/instruments", {}, alice).json();
  REQUIRE(list["uploaded"].size() == 1);
  CHECK(list["uploaded"][0]["inspectable"] == true);
  CHECK(list["lab"].size() == 1);

  // Removal: refused while it is being inspected, then done; its id stays taken until a restart.
  f.flight.inspecting = "dmm";
  CHECK(http_call(f.port, verb::delete_, "/api/instruments/dmm", {}, root).status == 409);
  f.flight.inspecting.clear();
  CHECK(http_call(f.port, verb::delete_, "/api/instruments/dmm", {}, root).status == 200);
  CHECK(http_call(f.port, verb::post, "/api/instruments", upload("dmm").dump(), root).status == 409);
  CHECK(http_call(f.port, verb::patch, "/api/instruments/dmm", {}, root).status == 405);
  CHECK(http_call(f.port, verb::get, "/api/instruments/dmm/elsewhere", {}, root).status == 404);
}

TEST_CASE("web: an upload placed as it comes is inspectable at once, and refused there nothing is stored") {
  ServerFixture f;
  const std::string root = login_cookie(f.port, "root", "root-pw");
  json body = upload("scope2");
  body["position_m"] = {6.0, 0.6, 0.8};  // inside the bench
  body["yaw_deg"] = 180;
  CHECK(http_call(f.port, verb::post, "/api/instruments", body.dump(), root).status == 422);
  CHECK(http_call(f.port, verb::get, "/api/instruments", {}, root).json()["uploaded"].empty());
  body["position_m"] = {5.6, 0.6, 1.0};
  const HttpResult created = http_call(f.port, verb::post, "/api/instruments", body.dump(), root);
  REQUIRE(created.status == 201);
  CHECK(created.json()["inspectable"] == true);
  CHECK(f.flight.placed.size() == 1);
  body.erase("yaw_deg");
  body["id"] = "scope3";
  CHECK(http_call(f.port, verb::post, "/api/instruments", body.dump(), root).status == 400);  // a position without its yaw
}

TEST_CASE("web: an uploaded template too weak to track, of the wrong aspect or size, is refused with 422") {
  ServerFixture f;
  const std::string root = login_cookie(f.port, "root", "root-pw");
  const auto post = [&](const json& j) { return http_call(f.port, verb::post, "/api/instruments", j.dump(), root); };
  json b = upload("weak");
  b["image_base64"] = panel_png_base64(400, 200, 6);  // six rectangles: a few corners, most of the panel bare
  const HttpResult weak = post(b);
  CHECK(weak.status == 422);
  const std::string why = weak.json()["error"];
  CHECK(why.find("too weak") != std::string::npos);
  CHECK(why.find("% of the panel textured") != std::string::npos);
  b["image_base64"] = panel_png_base64(400, 400);
  CHECK(post(b).status == 422);  // square photo of a 2:1 panel
  b["image_base64"] = panel_png_base64(60, 30, 20);
  CHECK(post(b).status == 422);  // under 64 px a side
  b = upload("big");
  b["depth_m"] = 5;
  CHECK(post(b).status == 400);
  CHECK(http_call(f.port, verb::post, "/api/instruments", upload("x").dump(), root, "text/plain").status == 415);
}

TEST_CASE("instrument placement: inside the room, clear of benches and the platform, on a bench's top") {
  const LabOutline lab = scripted_lab_outline();
  InstrumentSpec s;
  s.width_m = 0.3;
  s.height_m = 0.2;
  s.depth_m = 0.3;
  s.T_world_object = panel_pose({5.85, -1.2, 1.0}, std::numbers::pi);  // the lab file's oscilloscope
  CHECK(placement_problem(s, lab).empty());
  s.T_world_object = panel_pose({5.85, -1.2, 0.95}, std::numbers::pi);  // its bottom edge 5 cm into the bench
  CHECK(placement_problem(s, lab).find("bench_east") != std::string::npos);
  s.T_world_object = panel_pose({6.4, 0, 1.5}, std::numbers::pi);  // its housing through the wall
  CHECK(placement_problem(s, lab).find("not inside the room") != std::string::npos);
  s.T_world_object = panel_pose({0.0, 0.1, 0.1}, 0.0);
  CHECK(placement_problem(s, lab).find("platform") != std::string::npos);
  CHECK(placement_problem(s, LabOutline{}).empty());  // no lab file known: nothing to check against
}
