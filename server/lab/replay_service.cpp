#include "server/lab/replay_service.hpp"

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

#include "drone/replay/recording.hpp"

namespace labo::server {

using nlohmann::json;

std::string_view to_string(ReplayAudience audience) {
  return audience == ReplayAudience::Everyone ? "everyone" : "me";
}

std::optional<ReplayAudience> parse_replay_audience(std::string_view text) {
  if (text == "me") return ReplayAudience::Requester;
  if (text == "everyone") return ReplayAudience::Everyone;
  return std::nullopt;
}

std::string replay_status_json(const ReplayStatus& s, bool as_event) {
  json j = {{"name", s.name},
            {"by", s.by},
            {"audience", to_string(s.audience)},
            {"speed", s.speed},
            {"state", to_string(s.progress.state)},
            {"position_s", std::round(s.progress.position_s * 10.0) / 10.0},
            {"frames", s.progress.frames},
            {"navdata", s.progress.navdata},
            {"truncated", s.progress.truncated}};
  if (!s.progress.error.empty()) j["error"] = s.progress.error;
  if (as_event) j["type"] = "replay";
  return j.dump();
}

ReplayService::~ReplayService() {
  std::lock_guard lock(mutex_);
  player_.reset();
}

ReplayOutcome ReplayService::start(const std::string& by, const std::string& name, const std::filesystem::path& file,
                                   ReplayAudience audience, double speed) {
  std::lock_guard lock(mutex_);
  if (player_ && current_ && player_->progress().state == ReplayState::Playing)
    return {409, "a replay of '" + current_->name + "' by " + current_->by + " is playing: DELETE /api/replay first"};
  player_.reset();  // the last one has ended: its thread is done or ends now
  ReplayStatus status{name, by, audience, speed, {}};
  const std::optional<std::string> to = audience == ReplayAudience::Everyone ? std::nullopt : std::optional(by);
  // The sinks run on the player's thread: they use copies and the registry, never this service's lock.
  auto frames = [this, to](std::shared_ptr<const std::string> wire) { clients_.send_replay_frame(wire, to); };
  auto progress = [this, to, status](const ReplayProgress& p) {
    ReplayStatus now = status;
    now.progress = p;
    clients_.send_to_user(to, std::make_shared<const std::string>(replay_status_json(now, true)));
  };
  try {
    player_ = std::make_unique<RecordingPlayer>(file, speed, std::move(frames), std::move(progress), log_);
  } catch (const replay::RecordingError& e) {
    return {422, e.what()};
  }
  current_ = status;
  return {200, "playing '" + name + "' to " + (to ? by : std::string("everyone"))};
}

ReplayOutcome ReplayService::stop(const std::string& by) {
  std::lock_guard lock(mutex_);
  if (!player_ || player_->progress().state != ReplayState::Playing) return {404, "no replay is playing"};
  player_->stop();
  return {200, "stopped '" + current_->name + "' (" + by + ")"};
}

std::optional<ReplayStatus> ReplayService::status() const {
  std::lock_guard lock(mutex_);
  if (!current_) return std::nullopt;
  ReplayStatus s = *current_;
  if (player_) s.progress = player_->progress();
  return s;
}

}  // namespace labo::server
