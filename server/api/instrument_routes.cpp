#include <algorithm>
#include <nlohmann/json.hpp>
#include <variant>

#include "server/api/instrument_placement.hpp"
#include "server/api/rest_api.hpp"

// The admin's instruments: an upload is validated (its template strong enough to be found and
// tracked), stored, and once placed (in the upload or later by PUT .../placement) handed to the
// flight software, inspectable at once; in the simulated lab its panel is drawn where it was placed.
// Stored placed uploads are placed again when the server starts.
namespace labo::server {

using lab::InstrumentSpec;


namespace http = boost::beast::http;
using nlohmann::json;

namespace {

json uploaded_json(const UploadedInstrument& u, bool inspectable) {
  json j{{"id", u.id},
         {"name", u.name},
         {"width_m", u.width_m},
         {"height_m", u.height_m},
         {"depth_m", u.depth_m},
         {"width_px", u.width_px},
         {"height_px", u.height_px},
         {"strength", {{"sift_keypoints", u.strength.sift_keypoints},
                       {"strong_corners", u.strength.strong_corners},
                       {"textured_fraction", u.strength.textured_fraction}}},
         {"placed", u.placement.has_value()},
         {"inspectable", inspectable}};
  j["position_m"] = u.placement ? json{u.placement->x_m, u.placement->y_m, u.placement->z_m} : json(nullptr);
  j["yaw_deg"] = u.placement ? json(u.placement->yaw_deg) : json(nullptr);
  return j;
}

bool listed(const std::vector<InstrumentSummary>& instruments, const std::string& id) {
  for (const InstrumentSummary& i : instruments)
    if (i.id == id) return true;
  return false;
}

}  // namespace

HttpReply RestApi::instruments() {
  const std::vector<InstrumentSummary> flying = lab_.flight().instruments();
  const std::vector<UploadedInstrument> uploads = uploads_.list();
  json lab = json::array(), uploaded = json::array();
  for (const UploadedInstrument& u : uploads) uploaded.push_back(uploaded_json(u, listed(flying, u.id)));
  for (const InstrumentSummary& i : flying) {
    const bool from_upload = std::any_of(uploads.begin(), uploads.end(), [&](const UploadedInstrument& u) { return u.id == i.id; });
    if (!from_upload) lab.push_back({{"id", i.id}, {"name", i.name}, {"width_m", i.width_m}, {"height_m", i.height_m}});
  }
  return ok_json({{"lab", lab}, {"uploaded", uploaded}});
}

HttpReply RestApi::route_instruments(const HttpRequest& req, const std::string& path, const SessionInfo& session) {
  const http::verb m = req.method();
  if (path == "/api/instruments") {
    if (m != http::verb::post) return method_not_allowed("GET, POST");
    return add_instrument(req, session);
  }
  const std::string rest = path.substr(std::string("/api/instruments/").size());
  const auto slash = rest.find('/');
  if (slash == std::string::npos) {
    if (m != http::verb::delete_) return method_not_allowed("DELETE");
    return delete_instrument(rest, session);
  }
  if (rest.substr(slash) != "/placement") return HttpReply::error(http::status::not_found, "no route " + path);
  if (m != http::verb::put) return method_not_allowed("PUT");
  return place_instrument(req, rest.substr(0, slash), session);
}

HttpReply RestApi::add_instrument(const HttpRequest& req, const SessionInfo& session) {
  const json body = json::parse(req.body(), nullptr, false);
  const std::string id = body.is_object() && body.contains("id") && body["id"].is_string() ? body["id"].get<std::string>() : "";
  const HttpReply reply = [&] {
    std::lock_guard lock(instruments_mutex_);
    if (removed_instruments_.contains(id))
      return HttpReply::error(http::status::conflict, "instrument '" + id + "' was removed while the server runs: its id is free again after a restart");
    std::vector<std::string> reserved;
    for (const auto& i : lab_.flight().instruments()) reserved.push_back(i.id);
    auto result = uploads_.add(req.body(), reserved);
    if (auto* err = std::get_if<InstrumentError>(&result)) return HttpReply::error(static_cast<http::status>(err->status), err->message);
    const UploadedInstrument u = std::get<UploadedInstrument>(result);
    if (u.placement) {
      // Placed as uploaded: refused there, nothing stays stored.
      if (auto refusal = place_upload(u)) {
        uploads_.remove(u.id);
        return *refusal;
      }
    }
    return ok_json(uploaded_json(u, u.placement.has_value()), http::status::created);
  }();
  audit(session, "instrument_add", id, reply);
  return reply;
}

std::optional<HttpReply> RestApi::place_upload(const UploadedInstrument& u) {
  const InstrumentSpec spec = instrument_spec_of(u, uploads_.template_path(u.id));
  if (const std::string problem = placement_problem(spec, lab_.flight().lab_outline()); !problem.empty())
    return HttpReply::error(http::status::unprocessable_entity, "instrument '" + u.id + "' cannot stand there: " + problem);
  const CommandVerdict verdict = lab_.flight().add_instrument(spec);
  if (!verdict.accepted) return HttpReply::error(http::status::unprocessable_entity, verdict.reason);
  uploads_.set_placement(u.id, u.placement);
  return std::nullopt;
}

HttpReply RestApi::place_instrument(const HttpRequest& req, const std::string& id, const SessionInfo& session) {
  const HttpReply reply = [&] {
    std::lock_guard lock(instruments_mutex_);
    if (!InstrumentStore::valid_id(id)) return HttpReply::error(http::status::bad_request, "invalid instrument id '" + id + "'");
    std::optional<UploadedInstrument> u = uploads_.find(id);
    if (!u) {
      if (listed(lab_.flight().instruments(), id))
        return HttpReply::error(http::status::conflict, "instrument '" + id + "' is part of the lab description: move it in the lab file");
      return HttpReply::error(http::status::not_found, "no uploaded instrument '" + id + "'");
    }
    if (u->placement)
      return HttpReply::error(http::status::conflict, "instrument '" + id + "' is placed already: delete it and upload it again to move it");
    auto body = json_object_body(req, {"position_m", "yaw_deg"});
    if (auto* refusal = std::get_if<HttpReply>(&body)) return *refusal;
    auto placement = InstrumentStore::read_placement(std::get<json>(body));
    if (auto* err = std::get_if<InstrumentError>(&placement)) return HttpReply::error(static_cast<http::status>(err->status), err->message);
    u->placement = std::get<std::optional<InstrumentPlacement>>(placement);
    if (!u->placement) return HttpReply::error(http::status::bad_request, "'position_m' [x, y, z] and 'yaw_deg' are required");
    if (auto refusal = place_upload(*u)) return *refusal;
    return ok_json(uploaded_json(*u, true));
  }();
  audit(session, "instrument_place", id, reply);
  return reply;
}

HttpReply RestApi::delete_instrument(const std::string& id, const SessionInfo& session) {
  const HttpReply reply = [&] {
    std::lock_guard lock(instruments_mutex_);
    if (!InstrumentStore::valid_id(id)) return HttpReply::error(http::status::bad_request, "invalid instrument id '" + id + "'");
    const std::optional<UploadedInstrument> u = uploads_.find(id);
    if (!u) {
      if (listed(lab_.flight().instruments(), id))
        return HttpReply::error(http::status::conflict, "instrument '" + id + "' is part of the lab description");
      return HttpReply::error(http::status::not_found, "no uploaded instrument '" + id + "'");
    }
    if (u->placement && listed(lab_.flight().instruments(), id)) {
      const CommandVerdict verdict = lab_.flight().remove_instrument(id);
      if (!verdict.accepted) return HttpReply::error(http::status::conflict, verdict.reason);
      removed_instruments_.insert(id);
    }
    uploads_.remove(id);
    return ok_json({{"deleted", id}});
  }();
  audit(session, "instrument_delete", id, reply);
  return reply;
}

void RestApi::place_stored_instruments() {
  std::lock_guard lock(instruments_mutex_);
  for (const UploadedInstrument& u : uploads_.list()) {
    if (!u.placement || listed(lab_.flight().instruments(), u.id)) continue;
    // A refusal leaves it stored and not inspectable: GET /api/instruments shows it so.
    lab_.flight().add_instrument(instrument_spec_of(u, uploads_.template_path(u.id)));
  }
}

}  // namespace labo::server
