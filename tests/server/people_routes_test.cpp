#include <catch2/catch.hpp>
#include <fstream>
#include <numbers>
#include <opencv2/imgcodecs.hpp>

#include "core/candide3.hpp"
#include "localization/face/face_geometry.hpp"
#include "localization/face/face_pose_estimator.hpp"
#include "localization/face/textured_head_renderer.hpp"
#include "tests/server/support/server_fixture.hpp"
#include "tests/server/support/test_clients.hpp"

// The teacher's routes: faces registered from photos, the person face-follow follows, a student's
// turn ended with a reason. Photos are the astronaut head (assets/astronaut.png, from
// scripts/setup.sh) rendered through the AR.Drone 2.0's front camera.

using namespace labo;
using namespace labo::server;
using namespace labo::server::test;
using nlohmann::json;
using http::verb;

namespace {

std::string error_of(const HttpResult& r) { return std::to_string(r.status) + " " + r.json().value("error", ""); }

class HeadPhotos {
 public:
  HeadPhotos() {
    const cv::Mat photo = cv::imread((labo::source_root() / "assets" / "astronaut.png").string(), cv::IMREAD_GRAYSCALE);
    REQUIRE_FALSE(photo.empty());  // run scripts/setup.sh
    face::FacePoseEstimator estimator(face::default_face_config(), camera_);
    renderer_.emplace(candide_, face::texture_head_from_photo(estimator, candide_, photo, 0.063), camera_);
  }
  // The head `x_m` right of the optical axis, 0.8 m away, turned by yaw and pitch (degrees); PNG bytes.
  std::string png(double yaw_deg, double pitch_deg = 0, std::vector<double> xs_m = {0.0}) {
    cv::Mat img(camera_.height(), camera_.width(), CV_8UC1, cv::Scalar(120));
    for (double x : xs_m) {
      Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
      constexpr double kRad = std::numbers::pi / 180.0;
      T.linear() = face::head_rotation({yaw_deg * kRad, pitch_deg * kRad, 0.0});
      T.translation() = Eigen::Vector3d(x, -0.02, 0.8);
      renderer_->render(T, img);
    }
    return encode(img, ".png");
  }
  static std::string encode(const cv::Mat& img, const std::string& ext) {
    std::vector<std::uint8_t> bytes;
    cv::imencode(ext, img, bytes);
    return {bytes.begin(), bytes.end()};
  }

 private:
  PinholeCamera camera_ = PinholeCamera::ardrone2_front();
  Candide3Model candide_ = Candide3Model::load(Candide3Model::default_path());
  std::optional<face::TexturedHeadRenderer> renderer_;
};

struct Part {
  std::string name, value, filename{}, type{};
};

// A multipart/form-data body as a browser's FormData sends it.
std::string form(const std::vector<Part>& parts, const std::string& boundary = "labo-test-boundary") {
  std::string body;
  for (const Part& p : parts) {
    body += "--" + boundary + "\r\nContent-Disposition: form-data; name=\"" + p.name + "\"";
    if (!p.filename.empty()) body += "; filename=\"" + p.filename + "\"";
    body += "\r\n";
    if (!p.type.empty()) body += "Content-Type: " + p.type + "\r\n";
    body += "\r\n" + p.value + "\r\n";
  }
  return body + "--" + boundary + "--\r\n";
}
const std::string kFormType = "multipart/form-data; boundary=labo-test-boundary";

Part photo(const std::string& bytes, const std::string& field = "frontal", const std::string& type = "image/png") {
  return {field, bytes, field + ".png", type};
}

std::filesystem::path people_dir_of(const ServerSettings& s) { return s.people.face.people_dir; }

// A server whose teachers register faces into a folder of its own.
ServerFixture people_server(std::size_t max_body_bytes = 8 * 1024 * 1024) {
  return ServerFixture([max_body_bytes](ServerSettings& s) {
    s.people.face = face::default_face_config();
    s.people.face.people_dir = s.recordings_dir.parent_path() / "people";  // removed with the fixture's folder
    s.people.front_camera = PinholeCamera::ardrone2_front().intrinsics();
    s.clients.max_body_bytes = max_body_bytes;
  });
}

bool contains(const std::vector<std::string>& lines, const std::string& line) {
  return std::find(lines.begin(), lines.end(), line) != lines.end();
}

}  // namespace

TEST_CASE("web: a teacher registers a face from frontal photos, lists it, replaces it and deletes it") {
  ServerFixture f = people_server();
  HeadPhotos photos;
  const std::string tess = login_cookie(f.port, "tess", "tess-pw");
  const std::string frontal = photos.png(0);
  const HttpResult added = http_call(f.port, verb::post, "/api/people",
                                     form({{"name", "ada"}, photo(frontal), photo(photos.png(2)), {"ipd_mm", "64"}}), tess, kFormType);
  REQUIRE(added.status == 201);
  CHECK(added.json()["name"] == "ada");
  CHECK(added.json()["fit_rms_px"].get<double>() > 0);
  // The textured astronaut seen at 0.8 m fits CANDIDE-3 at ~2.8-3.0 px RMS (its portrait lens puts
  // the photograph's landmarks where the mesh fits them loosely; bench faces: 2.79 px); a wrong fit
  // is tens of pixels.
  CHECK(added.json()["fit_rms_px"].get<double>() < 4);
  CHECK(added.json()["interpupillary_distance_mm"].get<double>() == Approx(64));
  CHECK(added.json()["head_turn"].is_null());
  CHECK(std::filesystem::is_regular_file(people_dir_of(f.settings) / "ada.json"));
  CHECK_FALSE(std::filesystem::exists(people_dir_of(f.settings) / "ada.json.tmp"));

  const json list = http_call(f.port, verb::get, "/api/people", {}, tess).json();
  REQUIRE(list["people"].size() == 1);
  CHECK(list["people"][0]["name"] == "ada");
  CHECK(list["people"][0]["registration"]["frontal_photos"] == 2);
  CHECK(list["people"][0]["registration"]["by"] == "tess");
  CHECK(list["photo_size"] == json({{"width", 640}, {"height", 360}}));
  CHECK(list["max_upload_bytes"] == f.settings.clients.max_body_bytes);
  CHECK(list["followed"].is_null());

  CHECK(error_of(http_call(f.port, verb::post, "/api/people", form({{"name", "ada"}, photo(frontal)}), tess, kFormType)) ==
        "409 'ada' is registered already: send replace=true to replace the shape");
  const HttpResult replaced =
      http_call(f.port, verb::post, "/api/people", form({{"name", "ada"}, {"replace", "true"}, photo(frontal)}), tess, kFormType);
  CHECK(replaced.status == 201);
  CHECK(replaced.json()["replaced"] == true);

  CHECK(http_call(f.port, verb::delete_, "/api/people/ada", {}, tess).status == 200);
  CHECK(http_call(f.port, verb::delete_, "/api/people/ada", {}, tess).status == 404);
  CHECK(http_call(f.port, verb::get, "/api/people", {}, tess).json()["people"].empty());
  const auto actions = audit_actions(f);
  CHECK(contains(actions, "person_register ada ok"));
  CHECK(contains(actions, "person_register ada refused"));
  CHECK(contains(actions, "person_delete ada ok"));
  CHECK(contains(actions, "person_delete ada refused"));
}

TEST_CASE("web: a face registration refuses bad photos and bad forms with their status") {
  ServerFixture f = people_server(2 * 1024 * 1024);
  HeadPhotos photos;
  const std::string tess = login_cookie(f.port, "tess", "tess-pw");
  const std::string alice = login_cookie(f.port, "alice", "alice-pw");
  const std::string frontal = photos.png(0);
  const auto post = [&](const std::vector<Part>& parts, const std::string& cookie = {}) {
    return http_call(f.port, verb::post, "/api/people", form(parts), cookie.empty() ? tess : cookie, kFormType);
  };
  // Refused by the face code (the worker): no face, several faces, a turned head.
  const std::string blank = HeadPhotos::encode(cv::Mat(360, 640, CV_8UC1, cv::Scalar(120)), ".png");
  CHECK(error_of(post({{"name", "ada"}, photo(blank)})) == "422 frontal picture refused: no face found");
  CHECK(error_of(post({{"name", "ada"}, photo(photos.png(0, 0, {-0.2, 0.2}))})) ==
        "422 frontal picture refused: 2 faces found, expected one person");
  CHECK_THAT(error_of(post({{"name", "ada"}, photo(photos.png(35))})), Catch::StartsWith("422 frontal picture refused: head turned"));
  CHECK_THAT(error_of(post({{"name", "ada"}, photo(frontal), photo(blank)})),
             Catch::StartsWith("422 frontal picture 1 refused: no face found"));
  // Refused from the form alone (the I/O thread): size, type, name, fields.
  const std::string small = HeadPhotos::encode(cv::Mat(100, 120, CV_8UC1, cv::Scalar(90)), ".png");
  CHECK(error_of(post({{"name", "ada"}, photo(small)})) ==
        "422 frontal photo 1 (frontal.png) is 120x100, expected the front camera's 640x360: take the photos with the drone's "
        "front camera");
  const std::string jpeg_small = HeadPhotos::encode(cv::Mat(200, 300, CV_8UC1, cv::Scalar(90)), ".jpg");
  CHECK_THAT(error_of(post({{"name", "ada"}, photo(jpeg_small, "frontal", "image/jpeg")})), Catch::Contains("is 300x200"));
  CHECK(error_of(post({{"name", "ada"}, photo(frontal, "frontal", "text/plain")})) ==
        "415 frontal photo 1 (frontal.png) is sent as 'text/plain', expected image/png or image/jpeg");
  CHECK(error_of(post({{"name", "ada"}, photo("GIF89a not a png")})) ==
        "415 frontal photo 1 (frontal.png) is not a PNG or JPEG image (its first bytes say neither)");
  CHECK(post({{"name", "ada"}, photo(frontal.substr(0, 20))}).status == 400);  // a header cut short
  CHECK(error_of(post({{"name", "../ada"}, photo(frontal)})) == "400 'name' must be 1-64 characters of A-Z a-z 0-9 _ -, got '../ada'");
  CHECK(error_of(post({photo(frontal)})) == "400 the form needs a 'name'");
  CHECK(error_of(post({{"name", "ada"}})) == "400 the form needs at least one 'frontal' photo");
  CHECK(post({{"name", "ada"}, {"ipd_mm", "300"}, photo(frontal)}).status == 400);
  CHECK(post({{"name", "ada"}, {"replace", "maybe"}, photo(frontal)}).status == 400);
  CHECK(error_of(post({{"name", "ada"}, {"admin", "1"}, photo(frontal)})) ==
        "400 unknown or repeated field 'admin' (expected name, frontal, turn, replace, ipd_mm)");
  CHECK_THAT(error_of(http_call(f.port, verb::post, "/api/people", "--labo-test-boundary\r\nbroken", tess, kFormType)),
             Catch::StartsWith("400 malformed form: "));
  CHECK(error_of(http_call(f.port, verb::post, "/api/people", R"({"name":"ada"})", tess)) ==
        "415 send the photos as multipart/form-data (fields name, frontal, turn, replace, ipd_mm)");
  // Over the body limit: 413 from Content-Length, before a byte of the photos is read.
  CHECK(raw_status(f.port, "POST /api/people HTTP/1.1\r\nHost: x\r\nCookie: " + tess + "\r\nContent-Type: " + kFormType +
                               "\r\nContent-Length: 3000000\r\n\r\n") == 413);
  // Roles and sessions.
  CHECK(error_of(post({{"name", "ada"}, photo(frontal)}, alice)) == "403 role student may not do this: teachers and admins only");
  CHECK(http_call(f.port, verb::post, "/api/people", form({{"name", "ada"}, photo(frontal)}), {}, kFormType).status == 401);
  CHECK(http_call(f.port, verb::get, "/api/people", {}, alice).status == 403);
  CHECK(http_call(f.port, verb::put, "/api/people", {}, tess).status == 405);
  CHECK(http_call(f.port, verb::delete_, "/api/people/..", {}, tess).status == 400);
  CHECK(http_call(f.port, verb::delete_, "/api/people/ada", {}, alice).status == 403);
  CHECK(http_call(f.port, verb::get, "/api/people", {}, tess).json()["people"].empty());  // nothing refused was written
}

TEST_CASE("web: a head turn refines a registered face, and a head that does not turn is refused") {
  ServerFixture f = people_server();
  HeadPhotos photos;
  const std::string tess = login_cookie(f.port, "tess", "tess-pw");
  std::vector<Part> parts{{"name", "ada"}, photo(photos.png(0))}, still = parts;
  for (int i = 0; i < 40; ++i) {
    const double s = i / 40.0, wave = std::sin(2 * std::numbers::pi * std::fmod(2 * s, 1.0));
    parts.push_back(photo(photos.png(s < 0.5 ? 25 * wave : 0, s < 0.5 ? 0 : 15 * wave), "turn"));
    if (i < 12) still.push_back(photo(photos.png(0), "turn"));
  }
  CHECK_THAT(error_of(http_call(f.port, verb::post, "/api/people", form(still), tess, kFormType)),
             Catch::StartsWith("422 head turn refused: "));
  const HttpResult added = http_call(f.port, verb::post, "/api/people", form(parts), tess, kFormType);
  REQUIRE(added.status == 201);
  CHECK(added.json()["head_turn"]["views"].get<int>() >= 10);
  CHECK(added.json()["head_turn"]["yaw_span_deg"].get<double>() > 20);
  const json list = http_call(f.port, verb::get, "/api/people", {}, tess).json();
  CHECK(list["people"][0]["registration"]["head_turn_views"] == added.json()["head_turn"]["views"]);
}

TEST_CASE("web: the person a teacher chooses goes with every find_teacher, whoever sends it") {
  ServerFixture f = people_server();
  HeadPhotos photos;
  const std::string tess = login_cookie(f.port, "tess", "tess-pw");
  const std::string alice = login_cookie(f.port, "alice", "alice-pw");
  REQUIRE(http_call(f.port, verb::post, "/api/people", form({{"name", "ada"}, photo(photos.png(0))}), tess, kFormType).status == 201);
  const auto choose = [&](const std::string& body, const std::string& cookie = {}, const std::string& type = "application/json") {
    return http_call(f.port, verb::put, "/api/face_follow", body, cookie.empty() ? tess : cookie, type);
  };
  CHECK(error_of(choose(R"({"person":"bob"})")) == "404 nobody named 'bob' is registered");
  CHECK(choose(R"({"person":"a/b"})").status == 400);
  CHECK(choose(R"({"person":5})").status == 400);
  CHECK(choose(R"({"who":"ada"})").status == 400);
  CHECK(choose("person=ada", {}, "application/x-www-form-urlencoded").status == 415);
  CHECK(choose(R"({"person":"ada"})", alice).status == 403);
  CHECK(http_call(f.port, verb::get, "/api/face_follow", {}, alice).json()["followed"].is_null());
  REQUIRE(choose(R"({"person":"ada"})").status == 200);
  CHECK(http_call(f.port, verb::get, "/api/face_follow", {}, alice).json()["followed"] == "ada");
  CHECK(http_call(f.port, verb::get, "/api/people", {}, tess).json()["followed"] == "ada");

  // The teacher takes over and starts face-follow; then a student's "Find the teacher" follows ada too.
  WsClient teacher(f.port, tess);
  REQUIRE(teacher.wait_for("hello"));
  teacher.send(json{{"type", "take_over"}});
  teacher.send(json{{"type", "command"}, {"id", 1}, {"command", "find_teacher"}});
  REQUIRE(teacher.wait_for("ack"));
  teacher.send(json{{"type", "release_control"}});
  WsClient student(f.port, alice);
  REQUIRE(student.wait_for("hello"));
  student.send(json{{"type", "request_control"}});
  REQUIRE(student.wait_for("notice", [](const json& j) { return j["kind"] == "granted"; }));
  student.send(json{{"type", "command"}, {"id", 2}, {"command", "find_teacher"}});
  REQUIRE(student.wait_for("ack"));
  std::vector<std::string> followed;
  for (const MissionCommand& c : f.flight.requests_seen())
    if (c.kind == MissionCommandKind::FindTeacher) followed.push_back(c.person ? c.person->name : "none");
  CHECK(followed == std::vector<std::string>{"ada", "ada"});

  // Deleted: no longer chosen, the next find_teacher carries nobody.
  REQUIRE(http_call(f.port, verb::delete_, "/api/people/ada", {}, tess).status == 200);
  CHECK(http_call(f.port, verb::get, "/api/face_follow", {}, tess).json()["followed"].is_null());
  CHECK(contains(audit_actions(f), "face_follow_person ada ok"));
  CHECK(contains(audit_actions(f), "face_follow_person bob refused"));
}

TEST_CASE("web: a teacher ends a student's turn with a reason the student reads, and the queue shows times") {
  ServerFixture f = people_server();
  const std::string tess = login_cookie(f.port, "tess", "tess-pw");
  const std::string alice = login_cookie(f.port, "alice", "alice-pw");
  const std::string bob = login_cookie(f.port, "bob", "bob-pw");
  WsClient a(f.port, alice), b(f.port, bob);
  REQUIRE(a.wait_for("hello"));
  REQUIRE(b.wait_for("hello"));
  a.send(json{{"type", "request_control"}});
  REQUIRE(a.wait_for("notice", [](const json& j) { return j["kind"] == "granted"; }));
  b.send(json{{"type", "request_control"}});
  const auto queued = b.wait_for("control", [](const json& j) { return j["queue"].size() == 1 && j["seq"].get<int>() > 0; });
  REQUIRE(queued);
  CHECK((*queued)["queue"][0]["user"] == "bob");
  CHECK((*queued)["queue"][0]["waited_s"].get<double>() >= 0);
  CHECK((*queued)["held_s"].get<double>() >= 0);

  const auto end = [&](const std::string& body, const std::string& cookie = {}, const std::string& type = "application/json") {
    return http_call(f.port, verb::post, "/api/control/end_turn", body, cookie.empty() ? tess : cookie, type);
  };
  CHECK(error_of(end(R"({"user":"alice"})")) == "400 'reason' must be 1-200 characters of text: the student reads it");
  CHECK(end(R"({"user":"alice","reason":""})").status == 400);
  CHECK(end(json{{"user", "alice"}, {"reason", std::string(201, 'x')}}.dump()).status == 400);
  CHECK(end(R"({"user":"alice","reason":"a\u0007b"})").status == 400);
  CHECK(end(R"({"reason":"time's up"})").status == 400);
  CHECK(end(R"({"user":"alice","reason":"x","now":true})").status == 400);
  CHECK(error_of(end(R"({"user":"bob","reason":"time's up"})")) == "409 'bob' does not hold control ('alice' does)");
  CHECK(end("user=alice", {}, "text/plain").status == 415);
  CHECK(error_of(end(R"({"user":"alice","reason":"x"})", bob)) == "403 role student may not do this: teachers and admins only");
  CHECK(http_call(f.port, verb::get, "/api/control/end_turn", {}, tess).status == 405);

  const HttpResult ended = end(R"({"user":"alice","reason":"let bob measure the scope"})");
  REQUIRE(ended.status == 200);
  const auto notice = a.wait_for("notice", [](const json& j) { return j["kind"] == "ended"; });
  REQUIRE(notice);
  CHECK((*notice)["by"] == "tess");
  CHECK((*notice)["reason"] == "let bob measure the scope");
  CHECK(b.wait_for("notice", [](const json& j) { return j["kind"] == "granted"; }));
  CHECK(error_of(end(R"({"user":"alice","reason":"again"})")) == "409 'alice' does not hold control ('bob' does)");
  CHECK(contains(audit_actions(f), "end_turn alice ok"));
  CHECK(contains(audit_actions(f), "end_turn bob refused"));
}

TEST_CASE("web: a server without a people folder says so") {
  ServerFixture f;
  const std::string tess = login_cookie(f.port, "tess", "tess-pw");
  CHECK(error_of(http_call(f.port, verb::get, "/api/people", {}, tess)) == "503 this server registers no faces (no face.people_dir)");
}
