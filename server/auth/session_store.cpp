#include "server/auth/session_store.hpp"

#include <fstream>
#include <nlohmann/json.hpp>

namespace labo::server {

using nlohmann::json;

SessionStore::SessionStore(const std::vector<UserAccount>& users, double idle_timeout_s, double login_attempts_per_min,
                           std::filesystem::path sessions_file)
    : idle_timeout_s_(idle_timeout_s),
      login_rate_per_s_(login_attempts_per_min / 60.0),
      file_(std::move(sessions_file)),
      dummy_(PasswordHash::create("labodrone-dummy", PasswordHash::kMinIterations)) {
  for (const UserAccount& u : users)
    if (auto hash = PasswordHash::parse(u.password_hash)) accounts_.emplace(u.name, Account{u, std::move(*hash)});
  load();
}

LoginResult SessionStore::login(const std::string& user, const std::string& password, const std::string& remote,
                                double now_s) {
  std::optional<Account> account;
  {
    std::lock_guard lock(mutex_);
    if (login_buckets_.size() > 10000) login_buckets_.clear();  // bound the table against address churn
    auto [it, inserted] = login_buckets_.try_emplace(remote, login_rate_per_s_, login_rate_per_s_ * 60.0);
    if (!it->second.take(now_s)) return {LoginOutcome::RateLimited, {}};
    if (const auto found = accounts_.find(user); found != accounts_.end()) account = found->second;
  }
  // Hash outside the lock: it takes tens of milliseconds by design.
  const bool ok = account ? account->hash.verify(password) : (dummy_.verify(password), false);
  if (!ok) return {LoginOutcome::BadCredentials, {}};
  std::lock_guard lock(mutex_);
  const std::string token =
      signer_ ? signer_->issue(user, account->account.role, now_s + idle_timeout_s_) : random_hex(32);
  const std::string key = sha256_hex(token);
  SessionInfo s{"", key.substr(0, 16), user, account->account.role, now_s, now_s};
  expire(now_s);
  sessions_[key] = s;
  save();
  s.token = token;
  return {LoginOutcome::Ok, s};
}

std::optional<SessionInfo> SessionStore::authenticate(const std::string& token, double now_s) {
  const std::string key = sha256_hex(token);
  std::lock_guard lock(mutex_);
  auto it = sessions_.find(key);
  if (it == sessions_.end() && signer_ && !revoked_until_s_.contains(key)) {  // a login at another lab of the front
    const auto claims = signer_->verify(token, now_s);
    const auto account = claims ? accounts_.find(claims->user) : accounts_.end();
    if (account == accounts_.end() || account->second.account.role != claims->role) return std::nullopt;
    it = sessions_.emplace(key, SessionInfo{"", key.substr(0, 16), claims->user, claims->role, now_s, now_s}).first;
    save();
  }
  if (it == sessions_.end()) return std::nullopt;
  if (now_s - it->second.last_seen_s > idle_timeout_s_) {
    sessions_.erase(it);
    save();
    return std::nullopt;
  }
  it->second.last_seen_s = now_s;
  seen_changed_ = true;
  SessionInfo s = it->second;
  s.token = token;
  return s;
}

void SessionStore::logout(const std::string& token) {
  std::lock_guard lock(mutex_);
  const std::string key = sha256_hex(token);
  revoke(key, unix_now_s());
  if (sessions_.erase(key)) save();
}

void SessionStore::share_with(SessionSigner signer) {
  std::lock_guard lock(mutex_);
  signer_ = std::move(signer);
}

void SessionStore::revoke(const std::string& key, double now_s) {
  if (signer_) revoked_until_s_[key] = now_s + idle_timeout_s_;  // a signed token expires by then
}

bool SessionStore::end(const std::string& id) {
  std::lock_guard lock(mutex_);
  const auto n = std::erase_if(sessions_, [&](const auto& kv) {
    if (kv.second.id == id) revoke(kv.first, unix_now_s());
    return kv.second.id == id;
  });
  if (n) save();
  return n > 0;
}

std::vector<SessionInfo> SessionStore::sessions(double now_s) {
  std::lock_guard lock(mutex_);
  expire(now_s);
  std::vector<SessionInfo> out;
  for (const auto& [key, s] : sessions_) out.push_back(s);
  return out;
}

std::vector<UserAccount> SessionStore::users() const {
  std::lock_guard lock(mutex_);
  std::vector<UserAccount> out;
  for (const auto& [name, a] : accounts_) out.push_back(a.account);
  return out;
}

std::vector<std::string> SessionStore::set_users(const std::vector<UserAccount>& users) {
  std::map<std::string, Account> accounts;
  for (const UserAccount& u : users)
    if (auto hash = PasswordHash::parse(u.password_hash)) accounts.emplace(u.name, Account{u, std::move(*hash)});
  std::lock_guard lock(mutex_);
  std::vector<std::string> ended;
  for (const auto& [name, old] : accounts_) {
    const auto now = accounts.find(name);
    if (now == accounts.end() || now->second.account.role != old.account.role) ended.push_back(name);
  }
  accounts_ = std::move(accounts);
  const auto n = std::erase_if(sessions_, [&](const auto& kv) {
    return std::find(ended.begin(), ended.end(), kv.second.user) != ended.end();
  });
  if (n) save();
  return ended;
}

void SessionStore::save_if_changed(double now_s, bool force) {
  std::lock_guard lock(mutex_);
  if (!seen_changed_ || (!force && now_s - last_save_s_ < kIdleSaveInterval_s)) return;
  last_save_s_ = now_s;
  save();
}

void SessionStore::expire(double now_s) {
  if (std::erase_if(sessions_, [&](const auto& kv) { return now_s - kv.second.last_seen_s > idle_timeout_s_; })) save();
  std::erase_if(revoked_until_s_, [&](const auto& kv) { return kv.second <= now_s; });
}

void SessionStore::save() {
  seen_changed_ = false;
  if (file_.empty()) return;
  json list = json::array();
  for (const auto& [key, s] : sessions_)
    list.push_back({{"token_sha256", key}, {"user", s.user}, {"role", to_string(s.role)}, {"created_s", s.created_s},
                    {"last_seen_s", s.last_seen_s}});
  // Written beside, then renamed over: a crash leaves the old file or the new one, never half of one.
  std::error_code ec;
  std::filesystem::create_directories(file_.parent_path(), ec);
  const std::filesystem::path tmp = file_.string() + ".tmp";
  {
    std::ofstream out(tmp, std::ios::trunc);
    out << json{{"sessions", list}}.dump() << "\n";
    if (!out) return;
  }
  std::filesystem::permissions(tmp, std::filesystem::perms::owner_read | std::filesystem::perms::owner_write, ec);
  std::filesystem::rename(tmp, file_, ec);
}

void SessionStore::load() {
  if (file_.empty()) return;
  std::ifstream in(file_);
  if (!in) return;
  // A damaged file costs the users a login, never the start: whatever cannot be read is dropped.
  const json j = json::parse(in, nullptr, false);
  if (j.is_discarded() || !j.is_object() || !j.contains("sessions") || !j["sessions"].is_array()) return;
  for (const json& s : j["sessions"]) {
    if (!s.is_object()) continue;
    const std::string key = s.value("token_sha256", ""), user = s.value("user", ""), role = s.value("role", "");
    const auto account = accounts_.find(user);
    if (key.size() != 64 || account == accounts_.end() || to_string(account->second.account.role) != role) continue;
    const auto number = [&](const char* name) { return s.contains(name) && s[name].is_number() ? s[name].get<double>() : 0.0; };
    sessions_[key] = SessionInfo{"", key.substr(0, 16), user, account->second.account.role, number("created_s"), number("last_seen_s")};
  }
}

}  // namespace labo::server
