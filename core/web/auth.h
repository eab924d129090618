// The carer's login: the password file, sessions and the login rate limit.
//
// The password is stored as a libsodium crypto_pwhash_str string (Argon2id, a random salt,
// the cost parameters inside the string) in <state dir>/password, mode 0600; the plain
// password is never written. Sessions live in memory only: restarting Marvin logs everyone
// out. Each session has its own CSRF token, which every change must carry.
//
// Sessions and LoginLimiter are used on the web server's thread only (not thread-safe).
#pragma once

#include <chrono>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <string_view>

namespace marvin::web {

using Clock = std::chrono::steady_clock;

// Cost of the password hash. kInteractive is libsodium's interactive level (~0.1 s, 64 MiB);
// kMinimum exists so tests do not spend seconds hashing, and is never used by `marvin`.
enum class HashCost { kInteractive, kMinimum };

// Writes the hash of `password` to `file` (atomically, mode 0600; the folder is created).
// Throws std::runtime_error when the password is shorter than 8 characters or the file
// cannot be written (naming it).
void set_password(const std::filesystem::path& file, std::string_view password,
                  HashCost cost = HashCost::kInteractive);
bool password_is_set(const std::filesystem::path& file);
// False when no password is set or it does not match.
bool check_password(const std::filesystem::path& file, std::string_view password);

// 32 random bytes as 64 hex digits.
std::string random_token();
// Constant-time comparison of two tokens.
bool same_token(std::string_view a, std::string_view b);

struct Session {
  std::string id;    // the cookie's value
  std::string csrf;  // the X-CSRF-Token every change must send
  Clock::time_point expires;
};

class Sessions {
 public:
  explicit Sessions(std::chrono::seconds ttl) : ttl_(ttl) {}
  Session create(Clock::time_point now);
  // The session, unless unknown or expired (an expired one is forgotten).
  std::optional<Session> find(std::string_view id, Clock::time_point now);
  void remove(std::string_view id);
  std::chrono::seconds ttl() const { return ttl_; }

 private:
  std::chrono::seconds ttl_;
  std::map<std::string, Session, std::less<>> sessions_;
};

// At most `attempts` failed logins per client address per minute.
class LoginLimiter {
 public:
  explicit LoginLimiter(int attempts) : attempts_(attempts) {}
  // nullopt if `client` may try now, else how long it must wait.
  std::optional<std::chrono::seconds> wait_time(const std::string& client, Clock::time_point now);
  void failed(const std::string& client, Clock::time_point now);
  void succeeded(const std::string& client) { failures_.erase(client); }

 private:
  struct Failures {
    Clock::time_point window_start;
    int count = 0;
  };
  int attempts_;
  std::map<std::string, Failures> failures_;
};

}  // namespace marvin::web
