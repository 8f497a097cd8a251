#pragma once
// Logged-in sessions: a random 256-bit token per login, carried by the browser as an HttpOnly cookie
// (or by scripts as "Authorization: Bearer <token>"), expiring after an idle timeout. Passwords are
// checked against the salted PBKDF2 hashes of the configured users. Times are Unix seconds.
//
// With a sessions file, sessions survive a restart: the file keeps each session by its token's
// SHA-256 only (a copy of the file logs nobody in), is replaced atomically at each login, logout and
// end, and at most every `kIdleSaveInterval_s` for the last-seen times. At start, sessions of
// users that no longer exist or whose role changed are dropped; idle ones expire as always.
// Thread-safe.
#include <chrono>
#include <filesystem>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "server/auth/password_hash.hpp"
#include "server/auth/session_signer.hpp"
#include "server/auth/token_bucket.hpp"
#include "server/server_settings.hpp"

namespace labo::server {

// The clock sessions are kept on: Unix seconds, so that a session's times mean the same after a restart.
inline double unix_now_s() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

struct SessionInfo {
  std::string token;  // as presented by the client (empty in listings)
  std::string id;     // a public name of the session: the first 16 hex digits of its token's SHA-256
  std::string user;
  Role role = Role::Student;
  double created_s = 0;
  double last_seen_s = 0;
};

enum class LoginOutcome { Ok, BadCredentials, RateLimited };

struct LoginResult {
  LoginOutcome outcome = LoginOutcome::BadCredentials;
  SessionInfo session;
};

class SessionStore {
 public:
  static constexpr double kIdleSaveInterval_s = 30;

  SessionStore(const std::vector<UserAccount>& users, double idle_timeout_s, double login_attempts_per_min,
               std::filesystem::path sessions_file = {});

  // `remote` (the client's address) is rate limited: PBKDF2 is deliberately slow.
  LoginResult login(const std::string& user, const std::string& password, const std::string& remote, double now_s);
  std::optional<SessionInfo> authenticate(const std::string& token, double now_s);
  // From now on, logins issue tokens signed with the labs' shared key, and a token signed by another
  // lab of the same front is a session here too (session_signer.hpp).
  void share_with(SessionSigner signer);
  void logout(const std::string& token);
  // Ends the session named `id` (SessionInfo::id); false when there is none.
  bool end(const std::string& id);
  std::vector<SessionInfo> sessions(double now_s);
  std::vector<UserAccount> users() const;
  // Replaces the accounts (users added, removed, re-roled or given a new password). The sessions of
  // a removed user, or of a user whose role changed, end: their names are returned.
  std::vector<std::string> set_users(const std::vector<UserAccount>& users);
  // Saves the last-seen times if they changed and the last save is older than kIdleSaveInterval_s
  // (or `force`). Called by the server's tick and at shutdown.
  void save_if_changed(double now_s, bool force = false);

 private:
  void expire(double now_s);  // with mutex_ held
  void save();                // with mutex_ held
  void load();

  struct Account {
    UserAccount account;
    PasswordHash hash;
  };
  std::map<std::string, Account> accounts_;  // guarded by mutex_
  double idle_timeout_s_;
  double login_rate_per_s_;
  std::filesystem::path file_;
  PasswordHash dummy_;  // verified against for unknown users, so timing does not reveal names
  mutable std::mutex mutex_;
  std::map<std::string, SessionInfo> sessions_;  // by the token's SHA-256; SessionInfo::token empty
  std::map<std::string, TokenBucket> login_buckets_;
  bool seen_changed_ = false;
  double last_save_s_ = 0;
  std::optional<SessionSigner> signer_;
  // Signed sessions ended here (logout, end), by their token's SHA-256, until their token has surely
  // expired: a signature alone would bring them back. A removed or re-roled user's tokens need no
  // entry: authenticate() checks the claims against the accounts.
  std::map<std::string, double> revoked_until_s_;
  void revoke(const std::string& key, double now_s);  // with mutex_ held
};

}  // namespace labo::server
