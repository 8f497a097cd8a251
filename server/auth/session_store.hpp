#pragma once
// Logged-in sessions: a random 256-bit token per login, carried by the browser as an HttpOnly cookie
// (or by scripts as "Authorization: Bearer <token>"), expiring after an idle timeout. Passwords are
// checked against the salted PBKDF2 hashes of the configured users. Thread-safe.
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "server/auth/password_hash.hpp"
#include "server/auth/session_signer.hpp"
#include "server/auth/token_bucket.hpp"
#include "server/server_settings.hpp"

namespace labo {

struct SessionInfo {
  std::string token;
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
  SessionStore(const std::vector<UserAccount>& users, double idle_timeout_s, double login_attempts_per_min);

  // `remote` (the client's address) is rate limited: PBKDF2 is deliberately slow.
  LoginResult login(const std::string& user, const std::string& password, const std::string& remote, double now_s);
  std::optional<SessionInfo> authenticate(const std::string& token, double now_s);
  // From now on, logins issue tokens signed with the labs' shared key, and a token signed by another
  // lab of the same front is a session here too (session_signer.hpp).
  void share_with(SessionSigner signer);
  void logout(const std::string& token);
  std::vector<SessionInfo> sessions(double now_s);
  std::vector<UserAccount> users() const;

 private:
  void expire(double now_s);  // with mutex_ held

  struct Account {
    UserAccount account;
    PasswordHash hash;
  };
  std::map<std::string, Account> accounts_;
  double idle_timeout_s_;
  double login_rate_per_s_;
  PasswordHash dummy_;  // verified against for unknown users, so timing does not reveal names
  mutable std::mutex mutex_;
  std::map<std::string, SessionInfo> sessions_;
  std::map<std::string, TokenBucket> login_buckets_;
  std::optional<SessionSigner> signer_;
  // Signed tokens logged out here, until they expire: a signature alone would bring them back.
  std::map<std::string, double> revoked_until_unix_s_;
};

}  // namespace labo
