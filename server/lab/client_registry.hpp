#pragma once
// The connected clients and the fan-out to them: join, leave, send (the shape of Boost.Beast's
// chat-multi shared_state). A message is serialised once by the caller and shared by every client it
// goes to. A send copies the clients' weak pointers under the lock and delivers after unlocking: the
// delivery's reference may be a closing session's last, and its destructor leaves the registry,
// which takes the lock again (test "lab: a client whose last owner is a delivery leaves without a
// deadlock"). Thread-safe; nothing here blocks on a client (LabClient's sends only queue).
#include <array>
#include <atomic>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "server/auth/token_bucket.hpp"
#include "server/lab/control_queue.hpp"
#include "server/lab/lab_client.hpp"

namespace labo::server {

class ClientRegistry {
 public:
  using Message = std::shared_ptr<const std::string>;

  // Every client may send `messages_per_s` messages, `burst` at once.
  ClientRegistry(double messages_per_s, int burst) : messages_per_s_(messages_per_s), burst_(burst) {}

  void join(const std::shared_ptr<LabClient>& client);
  void leave(ClientId client);

  enum class Admission { Admitted, RateLimited, NotJoined };
  // One of the client's message tokens, taken at `now_s`.
  Admission admit(ClientId client, double now_s);

  void send(const Message& message);  // to every client
  void send_to(ClientId client, const Message& message);
  void send_each(const std::vector<std::pair<ClientId, Message>>& messages);  // each to its client
  // Video, to the clients that watch its path: a JPEG frame to their video slot, an access unit (and
  // its geometry) to their H.264 queue, the geometry alone as an event to the Geometry path's.
  void set_video(ClientId client, VideoPath path);
  // The H.264 renditions whose units the client needs (RenditionSwitch::needed(); the source only
  // until it says otherwise). True when the client now needs the low rendition and did not before.
  bool set_renditions(ClientId client, unsigned renditions);
  // H.264 viewers that need the low rendition: its encoder runs while there is one.
  std::size_t low_rendition_viewers() const { return low_viewers_.load(); }
  void send_frame(const Message& wire);
  void send_access_unit(const WireAccessUnit& unit);
  void send_reading_view(const Message& view);  // to every client's reading-view slot
  // A replayed recording's frame to the replay slot, or an event, of every client of `user` (all
  // the connections of that login), or of every client when `user` is empty.
  void send_replay_frame(const Message& wire, const std::optional<std::string>& user);
  void send_to_user(const std::optional<std::string>& user, const Message& message);
  std::size_t watching(VideoPath path) const { return viewers_[static_cast<std::size_t>(path)].load(); }
  void disconnect_all(const std::string& reason);
  // Disconnects the clients whose session `match` accepts; how many.
  std::size_t disconnect_where(const std::function<bool(const SessionInfo&)>& match, const std::string& reason);

  std::vector<Participant> participants() const;
  std::size_t size() const;

 private:
  struct Member {
    std::weak_ptr<LabClient> link;
    Participant who;
    TokenBucket bucket;
    VideoPath video = VideoPath::Jpeg;
    unsigned renditions = 1u << static_cast<unsigned>(Rendition::Source);
  };
  // The clients' weak pointers, copied under the lock: the caller locks them once it is released.
  std::vector<std::weak_ptr<LabClient>> links() const;
  std::vector<std::weak_ptr<LabClient>> links_of(const std::optional<std::string>& user) const;
  // Those of the clients watching `path` (and for H.264, needing `rendition`), into `out` (a
  // per-thread scratch vector: the per-frame fan-out does not allocate once it has grown).
  void links_watching(VideoPath path, Rendition rendition, std::vector<std::weak_ptr<LabClient>>& out) const;
  void count_viewers();  // under mutex_

  double messages_per_s_;
  int burst_;
  mutable std::mutex mutex_;
  std::unordered_map<ClientId, Member> members_;
  std::array<std::atomic<std::size_t>, 4> viewers_{};  // by VideoPath
  std::atomic<std::size_t> low_viewers_{0};
};

}  // namespace labo::server
