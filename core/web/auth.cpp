#include "web/auth.h"

#include <fcntl.h>
#include <sodium.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <iterator>
#include <stdexcept>

namespace marvin::web {

namespace fs = std::filesystem;

namespace {

void init_sodium() {
  if (sodium_init() < 0) throw std::runtime_error("libsodium could not be initialised");
}

std::string read_hash(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) return {};
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  while (!text.empty() && (text.back() == '\n' || text.back() == '\r')) text.pop_back();
  return text;
}

}  // namespace

void set_password(const fs::path& file, std::string_view password, HashCost cost) {
  init_sodium();
  if (password.size() < 8)
    throw std::runtime_error("the password must have at least 8 characters (it has " +
                             std::to_string(password.size()) + ")");
  char hash[crypto_pwhash_STRBYTES];
  const bool fast = cost == HashCost::kMinimum;
  if (crypto_pwhash_str(hash, password.data(), password.size(),
                        fast ? crypto_pwhash_OPSLIMIT_MIN : crypto_pwhash_OPSLIMIT_INTERACTIVE,
                        fast ? crypto_pwhash_MEMLIMIT_MIN : crypto_pwhash_MEMLIMIT_INTERACTIVE) !=
      0)
    throw std::runtime_error("not enough memory to hash the password");
  std::error_code ec;
  fs::create_directories(file.parent_path(), ec);
  const fs::path tmp = file.string() + ".tmp";
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0600);
  if (fd < 0)
    throw std::runtime_error("cannot write " + tmp.string() + ": " + std::strerror(errno));
  const std::string text = std::string(hash) + "\n";
  const bool written = ::write(fd, text.data(), text.size()) == static_cast<ssize_t>(text.size());
  const bool synced = ::fsync(fd) == 0;
  ::close(fd);
  if (!written || !synced || std::rename(tmp.c_str(), file.c_str()) != 0)
    throw std::runtime_error("cannot write " + file.string() + ": " + std::strerror(errno));
}

bool password_is_set(const fs::path& file) { return !read_hash(file).empty(); }

bool check_password(const fs::path& file, std::string_view password) {
  init_sodium();
  const std::string hash = read_hash(file);
  if (hash.empty()) return false;
  return crypto_pwhash_str_verify(hash.c_str(), password.data(), password.size()) == 0;
}

std::string random_token() {
  init_sodium();
  unsigned char bytes[32];
  randombytes_buf(bytes, sizeof bytes);
  char hex[sizeof bytes * 2 + 1];
  sodium_bin2hex(hex, sizeof hex, bytes, sizeof bytes);
  return hex;
}

bool same_token(std::string_view a, std::string_view b) {
  return a.size() == b.size() && !a.empty() && sodium_memcmp(a.data(), b.data(), a.size()) == 0;
}

Session Sessions::create(Clock::time_point now) {
  // Forget expired sessions so the table does not grow with abandoned logins.
  for (auto it = sessions_.begin(); it != sessions_.end();) {
    it = it->second.expires <= now ? sessions_.erase(it) : std::next(it);
  }
  Session s{random_token(), random_token(), now + ttl_};
  sessions_[s.id] = s;
  return s;
}

std::optional<Session> Sessions::find(std::string_view id, Clock::time_point now) {
  auto it = sessions_.find(id);
  if (it == sessions_.end()) return std::nullopt;
  if (it->second.expires <= now) {
    sessions_.erase(it);
    return std::nullopt;
  }
  return it->second;
}

void Sessions::remove(std::string_view id) {
  if (auto it = sessions_.find(id); it != sessions_.end()) sessions_.erase(it);
}

std::optional<std::chrono::seconds> LoginLimiter::wait_time(const std::string& client,
                                                            Clock::time_point now) {
  auto it = failures_.find(client);
  if (it == failures_.end()) return std::nullopt;
  const auto window_end = it->second.window_start + std::chrono::minutes(1);
  if (now >= window_end) {
    failures_.erase(it);
    return std::nullopt;
  }
  if (it->second.count < attempts_) return std::nullopt;
  return std::chrono::ceil<std::chrono::seconds>(window_end - now);
}

void LoginLimiter::failed(const std::string& client, Clock::time_point now) {
  Failures& f = failures_[client];
  if (f.count == 0 || now >= f.window_start + std::chrono::minutes(1)) f = {now, 0};
  ++f.count;
}

}  // namespace marvin::web
