#include "server/auth/session_store.hpp"

namespace labo {

SessionStore::SessionStore(const std::vector<UserAccount>& users, double idle_timeout_s, double login_attempts_per_min)
    : idle_timeout_s_(idle_timeout_s),
      login_rate_per_s_(login_attempts_per_min / 60.0),
      dummy_(PasswordHash::create("labodrone-dummy", PasswordHash::kMinIterations)) {
  for (const UserAccount& u : users) {
    auto hash = PasswordHash::parse(u.password_hash);
    if (hash) accounts_.emplace(u.name, Account{u, std::move(*hash)});
  }
}

LoginResult SessionStore::login(const std::string& user, const std::string& password, const std::string& remote,
                                double now_s) {
  {
    std::lock_guard lock(mutex_);
    if (login_buckets_.size() > 10000) login_buckets_.clear();  // bound the table against address churn
    auto [it, inserted] = login_buckets_.try_emplace(remote, login_rate_per_s_, login_rate_per_s_ * 60.0);
    if (!it->second.take(now_s)) return {LoginOutcome::RateLimited, {}};
  }
  // Hash outside the lock: it takes tens of milliseconds by design.
  const auto found = accounts_.find(user);
  const bool ok = found != accounts_.end() ? found->second.hash.verify(password) : (dummy_.verify(password), false);
  if (!ok) return {LoginOutcome::BadCredentials, {}};
  SessionInfo s{random_hex(32), user, found->second.account.role, now_s, now_s};
  std::lock_guard lock(mutex_);
  expire(now_s);
  sessions_[s.token] = s;
  return {LoginOutcome::Ok, s};
}

std::optional<SessionInfo> SessionStore::authenticate(const std::string& token, double now_s) {
  std::lock_guard lock(mutex_);
  auto it = sessions_.find(token);
  if (it == sessions_.end()) return std::nullopt;
  if (now_s - it->second.last_seen_s > idle_timeout_s_) {
    sessions_.erase(it);
    return std::nullopt;
  }
  it->second.last_seen_s = now_s;
  return it->second;
}

void SessionStore::logout(const std::string& token) {
  std::lock_guard lock(mutex_);
  sessions_.erase(token);
}

std::vector<SessionInfo> SessionStore::sessions(double now_s) {
  std::lock_guard lock(mutex_);
  expire(now_s);
  std::vector<SessionInfo> out;
  for (const auto& [token, s] : sessions_) out.push_back(s);
  return out;
}

std::vector<UserAccount> SessionStore::users() const {
  std::vector<UserAccount> out;
  for (const auto& [name, a] : accounts_) out.push_back(a.account);
  return out;
}

void SessionStore::expire(double now_s) {
  std::erase_if(sessions_, [&](const auto& kv) { return now_s - kv.second.last_seen_s > idle_timeout_s_; });
}

}  // namespace labo
