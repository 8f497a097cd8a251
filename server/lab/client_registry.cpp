#include "server/lab/client_registry.hpp"

#include <algorithm>

namespace labo::server {

void ClientRegistry::join(const std::shared_ptr<LabClient>& client) {
  const SessionInfo& s = client->session();
  std::lock_guard lock(mutex_);
  members_.insert_or_assign(client->id(), Member{client, Participant{client->id(), s.user, s.role},
                                                 TokenBucket(messages_per_s_, burst_)});
  count_viewers();
}

void ClientRegistry::leave(ClientId client) {
  std::lock_guard lock(mutex_);
  members_.erase(client);
  count_viewers();
}

void ClientRegistry::set_video(ClientId client, VideoPath path) {
  std::lock_guard lock(mutex_);
  if (const auto it = members_.find(client); it != members_.end()) it->second.video = path;
  count_viewers();
}

bool ClientRegistry::set_renditions(ClientId client, unsigned renditions) {
  std::lock_guard lock(mutex_);
  const auto it = members_.find(client);
  if (it == members_.end()) return false;
  const unsigned low = 1u << static_cast<unsigned>(Rendition::Low);
  const bool newly_low = (renditions & low) && !(it->second.renditions & low);
  it->second.renditions = renditions;
  count_viewers();
  return newly_low;
}

void ClientRegistry::count_viewers() {
  std::array<std::size_t, 4> count{};
  std::size_t low = 0;
  for (const auto& [id, m] : members_) {
    ++count[static_cast<std::size_t>(m.video)];
    low += m.video == VideoPath::H264 && (m.renditions & (1u << static_cast<unsigned>(Rendition::Low)));
  }
  for (std::size_t i = 0; i < count.size(); ++i) viewers_[i] = count[i];
  low_viewers_ = low;
}

ClientRegistry::Admission ClientRegistry::admit(ClientId client, double now_s) {
  std::lock_guard lock(mutex_);
  const auto it = members_.find(client);
  if (it == members_.end()) return Admission::NotJoined;
  return it->second.bucket.take(now_s) ? Admission::Admitted : Admission::RateLimited;
}

std::vector<std::weak_ptr<LabClient>> ClientRegistry::links() const {
  std::vector<std::weak_ptr<LabClient>> out;
  std::lock_guard lock(mutex_);
  out.reserve(members_.size());
  for (const auto& [id, m] : members_) out.push_back(m.link);
  return out;
}

std::vector<std::weak_ptr<LabClient>> ClientRegistry::links_of(const std::optional<std::string>& user) const {
  if (!user) return links();
  std::vector<std::weak_ptr<LabClient>> out;
  std::lock_guard lock(mutex_);
  for (const auto& [id, m] : members_)
    if (m.who.user == *user) out.push_back(m.link);
  return out;
}

void ClientRegistry::send_replay_frame(const Message& wire, const std::optional<std::string>& user) {
  for (const auto& weak : links_of(user))
    if (const auto client = weak.lock()) client->send_replay_frame(wire);
}

void ClientRegistry::send_to_user(const std::optional<std::string>& user, const Message& message) {
  for (const auto& weak : links_of(user))
    if (const auto client = weak.lock()) client->send_event(message);
}

void ClientRegistry::send(const Message& message) {
  for (const auto& weak : links())
    if (const auto client = weak.lock()) client->send_event(message);
}

void ClientRegistry::send_to(ClientId client, const Message& message) { send_each({{client, message}}); }

void ClientRegistry::send_each(const std::vector<std::pair<ClientId, Message>>& messages) {
  std::vector<std::pair<std::weak_ptr<LabClient>, const Message*>> targets;
  {
    std::lock_guard lock(mutex_);
    for (const auto& [id, message] : messages)
      if (const auto it = members_.find(id); it != members_.end()) targets.emplace_back(it->second.link, &message);
  }
  for (const auto& [weak, message] : targets)
    if (const auto client = weak.lock()) client->send_event(*message);
}

void ClientRegistry::links_watching(VideoPath path, Rendition rendition, std::vector<std::weak_ptr<LabClient>>& out) const {
  out.clear();
  const unsigned wanted = 1u << static_cast<unsigned>(rendition);
  std::lock_guard lock(mutex_);
  for (const auto& [id, m] : members_)
    if (m.video == path && (path == VideoPath::Jpeg || (m.renditions & wanted))) out.push_back(m.link);
}

void ClientRegistry::send_frame(const Message& wire) {
  thread_local std::vector<std::weak_ptr<LabClient>> targets;
  links_watching(VideoPath::Jpeg, Rendition::Source, targets);
  for (const auto& weak : targets)
    if (const auto client = weak.lock()) client->send_frame(wire);
  targets.clear();  // no client kept alive by the scratch vector
}

void ClientRegistry::send_access_unit(const WireAccessUnit& unit) {
  thread_local std::vector<std::weak_ptr<LabClient>> targets;
  links_watching(VideoPath::H264, unit.rendition, targets);
  for (const auto& weak : targets)
    if (const auto client = weak.lock()) client->send_access_unit(unit);
  // The media server forwards the source rendition: its geometry is the one matched by RTP timestamp.
  if (unit.geometry && unit.rendition == Rendition::Source && watching(VideoPath::Geometry) > 0) {
    links_watching(VideoPath::Geometry, Rendition::Source, targets);
    for (const auto& weak : targets)
      if (const auto client = weak.lock()) client->send_event(unit.geometry);
  }
  targets.clear();
}

void ClientRegistry::send_reading_view(const Message& view) {
  for (const auto& weak : links())
    if (const auto client = weak.lock()) client->send_reading_view(view);
}

void ClientRegistry::disconnect_all(const std::string& reason) {
  disconnect_where([](const SessionInfo&) { return true; }, reason);
}

std::size_t ClientRegistry::disconnect_where(const std::function<bool(const SessionInfo&)>& match, const std::string& reason) {
  std::size_t n = 0;
  for (const auto& weak : links())
    if (const auto client = weak.lock(); client && match(client->session())) {
      client->disconnect(reason);
      ++n;
    }
  return n;
}

std::vector<Participant> ClientRegistry::participants() const {
  std::vector<Participant> out;
  std::lock_guard lock(mutex_);
  out.reserve(members_.size());
  for (const auto& [id, m] : members_) out.push_back(m.who);
  std::sort(out.begin(), out.end(), [](const Participant& a, const Participant& b) { return a.client < b.client; });
  return out;
}

std::size_t ClientRegistry::size() const {
  std::lock_guard lock(mutex_);
  return members_.size();
}

}  // namespace labo::server
