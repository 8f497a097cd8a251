#pragma once
// Recordings played back in the page (REST: POST /api/recordings/{name}/replay, GET and DELETE
// /api/replay): one replay at a time, to the connections of the admin who asked or to everyone
// connected. Its frames go to each client's replay slot (never its live video), its progress as
// "replay" events to the same clients. Thread-safe.
#include <filesystem>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>

#include "core/log.hpp"
#include "server/lab/client_registry.hpp"
#include "server/lab/recording_player.hpp"

namespace labo::server {

enum class ReplayAudience { Requester, Everyone };
std::string_view to_string(ReplayAudience audience);
// "me" (the requester's own connections) or "everyone".
std::optional<ReplayAudience> parse_replay_audience(std::string_view text);

struct ReplayStatus {
  std::string name;  // the recording's file name
  std::string by;    // who started it
  ReplayAudience audience = ReplayAudience::Requester;
  double speed = 1.0;
  ReplayProgress progress;
};

// {"name", "by", "audience", "speed", "state", "position_s", "frames", "navdata", "truncated", "error"}:
// the REST status, and with "type": "replay" the clients' event.
std::string replay_status_json(const ReplayStatus& status, bool as_event);

struct ReplayOutcome {
  int status = 200;     // HTTP: 200, 404 (nothing plays), 409 (one plays already), 422 (not a recording)
  std::string message;  // the refusal, or what happened
};

class ReplayService {
 public:
  static constexpr double kMinSpeed = 0.25, kMaxSpeed = 8.0;

  ReplayService(ClientRegistry& clients, Logger log) : clients_(clients), log_(std::move(log)) {}
  ~ReplayService();  // the player stops before the clients it sends to are gone

  // Plays `file` (named `name` to the clients) for `by`. Refused with 409 while another replay plays
  // (stop it first: two replays to one page would interleave), 422 when the file is no recording.
  ReplayOutcome start(const std::string& by, const std::string& name, const std::filesystem::path& file,
                      ReplayAudience audience, double speed);
  // Stops the replay playing (404 when none plays); its audience gets the "stopped" event.
  ReplayOutcome stop(const std::string& by);
  // The replay playing, or the last one (ended, stopped or failed); none before the first.
  std::optional<ReplayStatus> status() const;

 private:
  ClientRegistry& clients_;
  Logger log_;
  mutable std::mutex mutex_;  // current_, player_
  std::optional<ReplayStatus> current_;  // without progress: the player holds it
  std::unique_ptr<RecordingPlayer> player_;
};

}  // namespace labo::server
