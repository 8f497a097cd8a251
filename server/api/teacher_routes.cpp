#include <nlohmann/json.hpp>
#include <variant>

#include "server/api/rest_api.hpp"
#include "server/auth/permissions.hpp"

// The teacher's routes (teachers and admins): faces registered from photos, the person face-follow
// follows, and ending a student's turn with a reason (docs/web.md "The teacher's routes").
namespace labo::server {

namespace http = boost::beast::http;
using nlohmann::json;

namespace {

bool is_json_body(const HttpRequest& req) { return req[http::field::content_type].substr(0, 16) == "application/json"; }

json person_json(const RegisteredPerson& p) {
  json j{{"name", p.name}};
  if (!p.error.empty()) {
    j["error"] = p.error;
    return j;
  }
  j["fit_rms_px"] = p.fit_rms_px;
  j["interpupillary_distance_mm"] = p.interpupillary_distance_mm;
  j["registration"] = p.registration ? json{{"frontal_photos", p.registration->frontal_photos},
                                            {"head_turn_views", p.registration->head_turn_views},
                                            {"unix_s", p.registration->unix_s},
                                            {"by", p.registration->by}}
                                     : json(nullptr);
  return j;
}

json outcome_json(const RegistrationOutcome& o) {
  json turn = nullptr;
  if (o.turn)
    turn = {{"views", o.turn->views}, {"yaw_span_deg", o.turn->yaw_span_deg}, {"pitch_span_deg", o.turn->pitch_span_deg},
            {"rms_before_px", o.turn->rms_before_px}, {"rms_after_px", o.turn->rms_after_px}};
  return {{"name", o.person.name}, {"fit_rms_px", o.person.fit_rms_px},
          {"interpupillary_distance_mm", o.person.interpupillary_distance_m * 1000.0}, {"head_turn", turn},
          {"replaced", o.replaced}};
}

// Reason text for a student's notice: 1-200 characters, no control characters.
bool valid_reason(const std::string& text) {
  if (text.empty() || text.size() > 200) return false;
  for (unsigned char c : text)
    if (c < 0x20 || c == 0x7f) return false;
  return true;
}

}  // namespace

HttpReply RestApi::route_teacher(const HttpRequest& req, const std::string& path, const SessionInfo& session) {
  const http::verb m = req.method();
  if (path == "/api/face_follow" && m == http::verb::get) return followed_person();
  const Permission needed = path == "/api/control/end_turn" ? Permission::EndTurn : Permission::ManagePeople;
  if (!role_may(session.role, needed))
    return HttpReply::error(http::status::forbidden, "role " + to_string(session.role) + " may not do this: teachers and admins only");
  if (path == "/api/control/end_turn") {
    if (m != http::verb::post) return method_not_allowed("POST");
    return end_turn(req, session);
  }
  if (!people_) return HttpReply::error(http::status::service_unavailable, "this server registers no faces (no face.people_dir)");
  if (path == "/api/face_follow") {
    if (m != http::verb::put) return method_not_allowed("GET, PUT");
    return follow_person(req, session);
  }
  if (path == "/api/people") {
    if (m == http::verb::get) return people();
    if (m == http::verb::post) return register_person(req, session);
    return method_not_allowed("GET, POST");
  }
  if (m != http::verb::delete_) return method_not_allowed("DELETE");
  return delete_person(path.substr(12), session);
}

HttpReply RestApi::people() {
  json list = json::array();
  for (const RegisteredPerson& p : people_->list()) list.push_back(person_json(p));
  const CameraIntrinsics& camera = settings_.people.front_camera;
  const std::string followed = lab_.followed_person().name();
  return ok_json({{"people", list},
                  {"followed", followed.empty() ? json(nullptr) : json(followed)},
                  {"photo_size", {{"width", camera.width}, {"height", camera.height}}},
                  {"max_upload_bytes", settings_.clients.max_body_bytes},
                  {"max_waiting", FaceRegistrar::kMaxWaiting}});
}

HttpReply RestApi::register_person(const HttpRequest& req, const SessionInfo& session) {
  const CameraIntrinsics& camera = settings_.people.front_camera;
  const auto content_type = req[http::field::content_type];
  auto read = read_registration_form({content_type.data(), content_type.size()}, req.body(),
                                     FormLimits{.width = camera.width, .height = camera.height});
  HttpReply refusal;
  if (const auto* refused = std::get_if<FormRefusal>(&read)) {
    refusal = HttpReply::error(static_cast<http::status>(refused->status), refused->message);
  } else {
    RegistrationForm& form = std::get<RegistrationForm>(read);
    if (!form.replace && people_->exists(form.name)) {
      refusal = HttpReply::error(http::status::conflict, "'" + form.name + "' is registered already: send replace=true to replace the shape");
    } else {
      const std::string name = form.name;
      HttpReply later;
      later.deferred = [this, session, name, form = std::move(form)](std::function<void(HttpReply)> done) mutable {
        auto answer = [this, session, name, done](const RegistrationOutcome& o) {
          HttpReply reply = o.status == 201 ? ok_json(outcome_json(o), http::status::created)
                                            : HttpReply::error(static_cast<http::status>(o.status), o.error);
          audit(session, "person_register", name, reply,
                o.status == 201 ? "fit RMS " + std::to_string(o.person.fit_rms_px) + " px" : std::string());
          done(std::move(reply));
        };
        if (registrar_->submit(std::move(form), session.user, answer)) return;
        RegistrationOutcome busy;
        busy.status = 503;
        busy.error = "registrations are busy: " + std::to_string(FaceRegistrar::kMaxWaiting) + " wait already; retry in a few seconds";
        answer(busy);
      };
      return later;
    }
  }
  const auto name_part = std::get_if<RegistrationForm>(&read);
  audit(session, "person_register", name_part ? name_part->name : "", refusal);
  return refusal;
}

HttpReply RestApi::delete_person(const std::string& name, const SessionInfo& session) {
  const HttpReply reply = [&] {
    try {
      face::validate_person_name(name);
    } catch (const std::invalid_argument&) {
      return HttpReply::error(http::status::bad_request, "'" + name.substr(0, 80) + "' is not a person's name (1-64 of A-Z a-z 0-9 _ -)");
    }
    if (!people_->remove(name)) return HttpReply::error(http::status::not_found, "nobody named '" + name + "' is registered");
    // No longer chosen: a face-follow running keeps the shape it has; the next find_teacher
    // follows whom the flight software followed last.
    if (lab_.followed_person().name() == name) lab_.followed_person().set(nullptr);
    return ok_json({{"deleted", name}});
  }();
  audit(session, "person_delete", name, reply);
  return reply;
}

HttpReply RestApi::followed_person() {
  const std::string name = lab_.followed_person().name();
  return ok_json({{"followed", name.empty() ? json(nullptr) : json(name)}});
}

HttpReply RestApi::follow_person(const HttpRequest& req, const SessionInfo& session) {
  const HttpReply reply = choose_followed(req);
  const json body = json::parse(req.body(), nullptr, false);
  const json person = body.is_object() ? body.value("person", json()) : json();
  audit(session, "face_follow_person", person.is_string() ? person.get<std::string>() : "", reply);
  return reply;
}

HttpReply RestApi::choose_followed(const HttpRequest& req) {
  if (!is_json_body(req)) return HttpReply::error(http::status::unsupported_media_type, "send the body as application/json");
  auto body = json_object_body(req, {"person"});
  if (auto* refused = std::get_if<HttpReply>(&body)) return *refused;
  const json& j = std::get<json>(body);
  if (!j.contains("person") || !(j["person"].is_string() || j["person"].is_null()))
    return bad_request("'person' must be a registered person's name, or null for none");
  if (j["person"].is_null()) {
    lab_.followed_person().set(nullptr);
    return ok_json({{"followed", nullptr}});
  }
  const std::string name = j["person"];
  try {
    face::validate_person_name(name);
  } catch (const std::invalid_argument&) {
    return bad_request("'" + name.substr(0, 80) + "' is not a person's name (1-64 of A-Z a-z 0-9 _ -)");
  }
  if (!people_->exists(name)) return HttpReply::error(http::status::not_found, "nobody named '" + name + "' is registered");
  try {
    lab_.followed_person().set(people_->load(name));
  } catch (const std::exception& e) {
    return HttpReply::error(http::status::unprocessable_entity, e.what());
  }
  return ok_json({{"followed", name}, {"applies", "at the next find_teacher"}});
}

HttpReply RestApi::end_turn(const HttpRequest& req, const SessionInfo& session) {
  const HttpReply reply = [&] {
    if (!is_json_body(req)) return HttpReply::error(http::status::unsupported_media_type, "send the body as application/json");
    auto body = json_object_body(req, {"user", "reason"});
    if (auto* refused = std::get_if<HttpReply>(&body)) return *refused;
    const json& j = std::get<json>(body);
    if (!j.contains("user") || !j["user"].is_string()) return bad_request("'user' (the student holding control) must be a string");
    if (!j.contains("reason") || !j["reason"].is_string() || !valid_reason(j["reason"]))
      return bad_request("'reason' must be 1-200 characters of text: the student reads it");
    const RemoteLab::EndTurnResult r = lab_.end_turn(session, j["user"], j["reason"]);
    if (r.status != 200) return HttpReply::error(static_cast<http::status>(r.status), r.message);
    return ok_json({{"ended", j["user"]}, {"reason", j["reason"]}});
  }();
  const json body = json::parse(req.body(), nullptr, false);
  const auto field = [&](const char* key) {
    return body.is_object() && body.contains(key) && body[key].is_string() ? body[key].get<std::string>() : std::string();
  };
  audit(session, "end_turn", field("user"), reply, field("reason"));
  return reply;
}

}  // namespace labo::server
