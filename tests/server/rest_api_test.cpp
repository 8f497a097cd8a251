#include <catch2/catch.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "server/api/instrument_store.hpp"
#include "tests/server/support/server_fixture.hpp"
#include "tests/server/support/test_clients.hpp"

using namespace labo;
using namespace labo::server;
using namespace labo::server::test;
using nlohmann::json;
using http::verb;

namespace {


std::string textured_png_base64(int size) {
  cv::Mat img(size, size, CV_8UC3, cv::Scalar(200, 200, 200));
  cv::RNG rng(7);
  for (int i = 0; i < 400; ++i)
    cv::rectangle(img, cv::Rect(rng.uniform(0, size - 20), rng.uniform(0, size - 20), rng.uniform(5, 20), rng.uniform(5, 20)),
                  cv::Scalar(rng.uniform(0, 255), rng.uniform(0, 255), rng.uniform(0, 255)), cv::FILLED);
  std::vector<std::uint8_t> png;
  cv::imencode(".png", img, png);
  return base64_encode(png);
}

}  // namespace

TEST_CASE("web: REST health, login and every authentication error") {
  ServerFixture f;
  CHECK(http_call(f.port, verb::get, "/api/health").json()["status"] == "ok");
  CHECK(http_call(f.port, verb::post, "/api/health").status == 405);

  const auto login = [&](const std::string& body, const std::string& type = "application/json") {
    return http_call(f.port, verb::post, "/api/login", body, {}, type);
  };
  CHECK(login(R"({"user":"alice","password":"alice-pw"})").status == 200);
  CHECK(login(R"({"user":"alice","password":"nope"})").status == 401);
  CHECK(login(R"({"user":"alice","password":"nope"})").json()["error"] == "unknown user or wrong password");
  CHECK(login(R"({"user":"alice",)").status == 400);                                // malformed JSON
  CHECK(login(R"({"user":"alice","password":5})").status == 400);                   // wrong type
  CHECK(login(R"({"user":"alice","password":"alice-pw","admin":true})").json()["error"] == "unknown field 'admin'");
  CHECK(login(R"(["alice"])").status == 400);
  CHECK(login("user=alice", "application/x-www-form-urlencoded").status == 415);

  const std::string alice = login_cookie(f.port, "alice", "alice-pw");
  REQUIRE(!alice.empty());
  CHECK(http_call(f.port, verb::get, "/api/status").status == 401);
  CHECK(http_call(f.port, verb::get, "/api/status", {}, "labo_session=forged").status == 401);
  const HttpResult status = http_call(f.port, verb::get, "/api/status", {}, alice);
  CHECK(status.status == 200);
  CHECK(status.json().contains("control"));
  CHECK(http_call(f.port, verb::get, "/api/me", {}, alice).json()["role"] == "student");
  CHECK(http_call(f.port, verb::get, "/api/nope", {}, alice).status == 404);
  CHECK(http_call(f.port, verb::get, "/api/nope", {}, alice).json()["error"] == "no route /api/nope");
  // Student: 403 on everything administrative.
  for (const std::string path : {"/api/config", "/api/users", "/api/recordings", "/metrics"})
    CHECK(http_call(f.port, verb::get, path, {}, alice).status == 403);
  CHECK(http_call(f.port, verb::post, "/api/logout", {}, alice).status == 200);
  CHECK(http_call(f.port, verb::get, "/api/me", {}, alice).status == 401);
}

TEST_CASE("web: REST refuses oversize bodies from Content-Length before reading them") {
  ServerFixture f([](ServerSettings& s) { s.clients.max_body_bytes = 4096; });
  // No body follows: the server must answer from the header alone.
  CHECK(raw_status(f.port, "POST /api/login HTTP/1.1\r\nHost: x\r\nContent-Type: application/json\r\n"
                           "Content-Length: 100000000\r\n\r\n") == 413);
  // Chunked past the limit: Beast's body_limit.
  std::string chunked = "POST /api/login HTTP/1.1\r\nHost: x\r\nContent-Type: application/json\r\nTransfer-Encoding: chunked\r\n\r\n";
  for (int i = 0; i < 5; ++i) chunked += "400\r\n" + std::string(1024, 'a') + "\r\n";
  CHECK(raw_status(f.port, chunked) == 413);
  CHECK(raw_status(f.port, "GARBAGE\r\n\r\n") == 400);
  CHECK(raw_status(f.port, "GET / HTTP/1.1\r\nHost: x\r\nX: " + std::string(20000, 'a') + "\r\n\r\n") == 431);
}

TEST_CASE("web: REST admin config, users, recordings, metrics and static files") {
  ServerFixture f;
  const std::string root = login_cookie(f.port, "root", "root-pw");
  const std::string tess = login_cookie(f.port, "tess", "tess-pw");
  REQUIRE(!root.empty());
  REQUIRE(!tess.empty());

  const HttpResult config = http_call(f.port, verb::get, "/api/config", {}, root);
  REQUIRE(config.status == 200);
  json doc = config.json();
  CHECK(doc["server"]["port"] == 8080);
  // PUT: validated as on load, saved only when valid.
  json bad = doc;
  bad["server"]["port"] = 70000;
  HttpResult put = http_call(f.port, verb::put, "/api/config", bad.dump(), root);
  CHECK(put.status == 422);
  CHECK(put.json()["error"].get<std::string>().find("server.port") != std::string::npos);
  bad = doc;
  bad["server"]["prot"] = 1;
  CHECK(http_call(f.port, verb::put, "/api/config", bad.dump(), root).status == 422);
  CHECK(http_call(f.port, verb::put, "/api/config", "{", root).status == 400);
  CHECK(http_call(f.port, verb::put, "/api/config", "[1]", root).status == 400);
  CHECK(http_call(f.port, verb::put, "/api/config", doc.dump(), tess).status == 403);
  json good = doc;
  good["server"]["port"] = 8181;
  put = http_call(f.port, verb::put, "/api/config", good.dump(), root);
  CHECK(put.status == 200);
  CHECK(http_call(f.port, verb::get, "/api/config", {}, root).json()["server"]["port"] == 8181);

  const HttpResult users = http_call(f.port, verb::get, "/api/users", {}, tess);  // teachers see sessions
  REQUIRE(users.status == 200);
  CHECK(users.json()["users"].size() == 4);
  CHECK(users.json()["sessions"].size() == 2);
  CHECK(users.json()["users"].dump().find("password") == std::string::npos);

  const HttpResult recs = http_call(f.port, verb::get, "/api/recordings", {}, root);
  REQUIRE(recs.json()["recordings"].size() == 1);
  const HttpResult file = http_call(f.port, verb::get, "/api/recordings/flight1.ldrec", {}, root);
  CHECK(file.status == 200);
  CHECK(file.body == "recorded bytes");
  CHECK(http_call(f.port, verb::get, "/api/recordings/..%2Fconfig", {}, root).status == 400);
  CHECK(http_call(f.port, verb::get, "/api/recordings/missing.ldrec", {}, root).status == 404);

  const HttpResult metrics = http_call(f.port, verb::get, "/metrics", {}, root);
  CHECK(metrics.status == 200);
  CHECK(metrics.content_type.find("text/plain") == 0);
  CHECK(metrics.body.find("# TYPE labodrone_http_requests_total counter") != std::string::npos);
  CHECK(metrics.body.find("labodrone_login_failures_total 0") != std::string::npos);
  // The flight's gauges: each with its type line and one sample of a number.
  for (const std::string gauge : {"labodrone_battery_percent", "labodrone_link_quality", "labodrone_video_fps",
                                  "labodrone_slam_keyframes", "labodrone_slam_map_mib"}) {
    INFO(gauge);
    CHECK(metrics.body.find("# TYPE " + gauge + " gauge\n") != std::string::npos);
    const std::size_t at = metrics.body.find("\n" + gauge + " ");
    REQUIRE(at != std::string::npos);
    const std::size_t value = at + gauge.size() + 2, end = metrics.body.find('\n', value);
    REQUIRE(end != std::string::npos);
    std::size_t used = 0;
    CHECK_NOTHROW(std::stod(metrics.body.substr(value, end - value), &used));
    CHECK(used == end - value);
  }

  const HttpResult page = http_call(f.port, verb::get, "/");
  CHECK(page.status == 200);
  CHECK(page.content_type.find("text/html") == 0);
  CHECK(http_call(f.port, verb::get, "/lab.js").content_type.find("text/javascript") == 0);
  CHECK(http_call(f.port, verb::get, "/../config/default.json").status == 400);
  CHECK(http_call(f.port, verb::get, "/missing.html").status == 404);
  CHECK(http_call(f.port, verb::post, "/index.html", "{}").status == 405);
}

TEST_CASE("web: REST instruments are validated before they are stored") {
  ServerFixture f;
  const std::string root = login_cookie(f.port, "root", "root-pw");
  const std::string alice = login_cookie(f.port, "alice", "alice-pw");
  json body{{"id", "psu"}, {"name", "Power supply"}, {"width_m", 0.3}, {"height_m", 0.3},
            {"position_m", {2.0, -1.0, 1.0}}, {"yaw_deg", 180}, {"image_base64", textured_png_base64(256)}};
  CHECK(http_call(f.port, verb::post, "/api/instruments", body.dump(), alice).status == 403);
  const auto post = [&](const json& j) { return http_call(f.port, verb::post, "/api/instruments", j.dump(), root); };
  json b = body;
  b["width_m"] = -1;
  CHECK(post(b).status == 400);
  b = body;
  b["id"] = "Bad Id";
  CHECK(post(b).status == 400);
  b = body;
  b["colour"] = "red";
  CHECK(post(b).json()["error"] == "unknown field 'colour'");
  b = body;
  b["image_base64"] = "not base64 !";
  CHECK(post(b).status == 400);
  b = body;
  b["image_base64"] = base64_encode({1, 2, 3, 4});
  CHECK(post(b).status == 415);
  CHECK(post(b).json()["error"] == "'image_base64' is not a PNG or JPEG image");
  b = body;
  {
    std::vector<std::uint8_t> png;
    cv::imencode(".png", cv::Mat(200, 200, CV_8UC3, cv::Scalar(128, 128, 128)), png);
    b["image_base64"] = base64_encode(png);
  }
  CHECK(post(b).status == 422);
  CHECK(post(b).json()["error"].get<std::string>().find("too weak to be found and tracked") != std::string::npos);
  b = body;
  b["id"] = "oscilloscope";
  CHECK(post(b).status == 409);

  const HttpResult created = post(body);
  REQUIRE(created.status == 201);
  CHECK(created.json()["strength"]["strong_corners"].get<int>() >= planar::TemplateStrengthLimits{}.min_strong_corners);
  CHECK(created.json()["inspectable"] == true);
  CHECK(post(body).status == 409);
  const json list = http_call(f.port, verb::get, "/api/instruments", {}, alice).json();
  CHECK(list["lab"].size() == 1);
  CHECK(list["uploaded"].size() == 1);
  CHECK(http_call(f.port, verb::delete_, "/api/instruments/oscilloscope", {}, root).status == 409);
  CHECK(http_call(f.port, verb::delete_, "/api/instruments/psu", {}, root).status == 200);
  CHECK(http_call(f.port, verb::delete_, "/api/instruments/psu", {}, root).status == 404);
}
