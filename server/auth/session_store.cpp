#include "server/auth/session_store.hpp"

#include <chrono>

namespace labo {
namespace {

double unix_now_s() { return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count(); }

}  // namespace

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
  const Role role = found->second.account.role;
  std::lock_guard lock(mutex_);
  SessionInfo s{signer_ ? signer_->issue(user, role, unix_now_s() + idle_timeout_s_) : random_hex(32), user, role, now_s,
                now_s};
  expire(now_s);
  sessions_[s.token] = s;
  return {LoginOutcome::Ok, s};
}

std::optional<SessionInfo> SessionStore::authenticate(const std::string& token, double now_s) {
  std::lock_guard lock(mutex_);
  auto it = sessions_.find(token);
  if (it == sessions_.end() && signer_) {  // a login at another lab of the front
    const auto claims = revoked_until_unix_s_.contains(token) ? std::nullopt : signer_->verify(token, unix_now_s());
    const auto account = claims ? accounts_.find(claims->user) : accounts_.end();
    if (account == accounts_.end() || account->second.account.role != claims->role) return std::nullopt;
    it = sessions_.emplace(token, SessionInfo{token, claims->user, claims->role, now_s, now_s}).first;
  }
  if (it == sessions_.end()) return std::nullopt;
  if (now_s - it->second.last_seen_s > idle_timeout_s_) {
    sessions_.erase(it);
    return std::nullopt;
  }
  it->second.last_seen_s = now_s;
  return it->second;
}

void SessionStore::share_with(SessionSigner signer) {
  std::lock_guard lock(mutex_);
  signer_ = std::move(signer);
}

void SessionStore::logout(const std::string& token) {
  std::lock_guard lock(mutex_);
  sessions_.erase(token);
  if (!signer_) return;
  if (const auto claims = signer_->verify(token, unix_now_s())) revoked_until_unix_s_[token] = claims->expires_unix_s;
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
  const double unix_s = unix_now_s();
  std::erase_if(revoked_until_unix_s_, [&](const auto& kv) { return kv.second <= unix_s; });
}

}  // namespace labo
