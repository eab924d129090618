#include "telephony/baresip.h"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/socket.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <future>
#include <memory>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <vector>

#include "common/log.h"

extern char** environ;

namespace marvin::telephony {
namespace {

constexpr std::string_view kReadyBanner = "baresip is ready.";
constexpr std::size_t kTailBytes = 4096;
constexpr const char* kProbeToken = "marvin-ready";
// What baresip 1.0 prints when another program holds a port it was told to bind (it then
// exits with status 98, EADDRINUSE, for SIP; it runs on without a control socket for
// ctrl_tcp).
constexpr std::string_view kSipPortTaken = "SIP Transport failed: Address already in use";
constexpr std::string_view kCtrlPortTaken = "ctrl_tcp: failed to listen";
constexpr int kExitAddressInUse = 98;

void log_phone(LogLevel level, const std::string& message) { log(level, "phone", message); }

std::string json_string(const nlohmann::json& j, const char* key) {
  auto it = j.find(key);
  return it != j.end() && it->is_string() ? it->get<std::string>() : std::string();
}

bool json_true(const nlohmann::json& j, const char* key) {
  auto it = j.find(key);
  return it != j.end() && it->is_boolean() && it->get<bool>();
}

}  // namespace

Baresip::Baresip(PhoneSettings settings, std::filesystem::path config_dir, EventHandler on_event)
    : settings_(std::move(settings)), config_dir_(std::move(config_dir)),
      on_event_(std::move(on_event)) {}

Baresip::~Baresip() { stop(); }

void Baresip::start() {
  choose_ports();
  if (::pipe2(wake_pipe_, O_CLOEXEC | O_NONBLOCK) != 0) {
    throw std::runtime_error("phone: cannot create a pipe: " + std::string(std::strerror(errno)));
  }
  // The first child is spawned by the supervisor thread, like every restart: the child's
  // parent-death signal (spawn()) is tied to the thread that forked it, and this thread lives
  // exactly as long as the supervision. start() still throws what spawning threw.
  auto spawned = std::make_shared<std::promise<void>>();  // shared: set after start() may return
  std::future<void> result = spawned->get_future();
  thread_ = std::thread([this, spawned] {
    try {
      std::lock_guard lock(mutex_);
      spawn();
    } catch (...) {
      spawned->set_exception(std::current_exception());
      return;
    }
    spawned->set_value();
    run();
  });
  try {
    result.get();
  } catch (...) {
    thread_.join();
    throw;
  }
}

void Baresip::choose_ports() {
  sip_port_ = settings_.sip_port != 0 ? settings_.sip_port : choose_port_(true);
  ctrl_port_ = choose_port_(false);
  write_baresip_config(settings_, sip_port_, ctrl_port_, config_dir_);
}

bool Baresip::ports_lost() const {
  return output_tail_.find(kSipPortTaken) != std::string::npos ||
         output_tail_.find(kCtrlPortTaken) != std::string::npos;
}

void Baresip::spawn() {
  int out[2];
  if (::pipe2(out, O_CLOEXEC) != 0) {
    throw std::runtime_error("phone: cannot create a pipe: " + std::string(std::strerror(errno)));
  }
  // exec failures come back through this pipe (closed by a successful exec: EOF).
  int exec_error[2];
  if (::pipe2(exec_error, O_CLOEXEC) != 0) {
    const int saved = errno;
    ::close(out[0]);
    ::close(out[1]);
    throw std::runtime_error("phone: cannot create a pipe: " + std::string(std::strerror(saved)));
  }
  std::filesystem::path work = settings_.record_dir.empty() ? config_dir_ : settings_.record_dir;
  std::filesystem::create_directories(work);
  const std::string work_dir = work.string();
  const std::string program = settings_.baresip_program.string();
  const std::string dir = config_dir_.string();
  std::vector<char*> argv{const_cast<char*>(program.c_str()), const_cast<char*>("-f"),
                          const_cast<char*>(dir.c_str()), nullptr};
  const pid_t parent = ::getpid();
  // fork + exec rather than posix_spawn: only a forked child can ask the kernel to end it
  // when its parent dies (PR_SET_PDEATHSIG), so a Marvin killed with SIGKILL leaves no
  // baresip behind holding its ports. Between fork and exec the child calls only
  // async-signal-safe functions (the parent has other threads).
  const pid_t pid = ::fork();
  if (pid < 0) {
    const int saved = errno;
    for (int fd : {out[0], out[1], exec_error[0], exec_error[1]}) ::close(fd);
    throw std::runtime_error("phone: cannot start " + program + ": " + std::strerror(saved));
  }
  if (pid == 0) {
    // Signals the parent blocks (marvin run takes SIGINT and SIGTERM on a thread of its
    // own) must reach baresip: its stop and the parent-death signal are SIGTERM.
    sigset_t none;
    sigemptyset(&none);
    ::sigprocmask(SIG_SETMASK, &none, nullptr);
    int failed = 0;
    const int null_fd = ::open("/dev/null", O_RDONLY);
    if (null_fd < 0 || ::dup2(null_fd, STDIN_FILENO) < 0 || ::dup2(out[1], STDOUT_FILENO) < 0 ||
        ::dup2(out[1], STDERR_FILENO) < 0 || ::chdir(work_dir.c_str()) != 0 ||
        ::prctl(PR_SET_PDEATHSIG, SIGTERM) != 0) {
      failed = errno;
    } else if (::getppid() != parent) {
      ::_exit(0);  // the parent died before the signal was set up
    } else {
      ::execve(program.c_str(), argv.data(), environ);
      failed = errno;
    }
    [[maybe_unused]] auto written = ::write(exec_error[1], &failed, sizeof failed);
    ::_exit(127);
  }
  ::close(out[1]);
  ::close(exec_error[1]);
  int failed = 0;
  ssize_t got;
  do {
    got = ::read(exec_error[0], &failed, sizeof failed);
  } while (got < 0 && errno == EINTR);
  ::close(exec_error[0]);
  if (got == static_cast<ssize_t>(sizeof failed)) {
    ::close(out[0]);
    int status = 0;
    ::waitpid(pid, &status, 0);
    throw std::runtime_error("phone: cannot start " + program + ": " + std::strerror(failed));
  }
  pid_ = pid;
  out_fd_ = out[0];
  pidfd_ = static_cast<int>(::syscall(SYS_pidfd_open, pid, 0));
  ready_ = false;
  child_was_ready_ = false;
  started_at_ = std::chrono::steady_clock::now();
  output_tail_.clear();
  log_phone(LogLevel::kInfo, "baresip started (pid " + std::to_string(pid) + ", SIP port " +
                                 std::to_string(sip_port_) + ")");
}

void Baresip::wake() {
  if (wake_pipe_[1] >= 0) {
    const char byte = 1;
    [[maybe_unused]] auto written = ::write(wake_pipe_[1], &byte, 1);
  }
}

void Baresip::stop() {
  {
    std::lock_guard lock(mutex_);
    if (stopping_) return;
    stopping_ = true;
  }
  wake();
  if (thread_.joinable()) thread_.join();
  std::lock_guard lock(mutex_);
  close_control();
  if (pid_ > 0) {
    ::kill(pid_, SIGTERM);
    // baresip hangs up its calls on SIGTERM; give it a moment (waiting on the pidfd).
    if (pidfd_ >= 0) {
      pollfd p{pidfd_, POLLIN, 0};
      if (::poll(&p, 1, 2000) <= 0) ::kill(pid_, SIGKILL);
    }
    int status = 0;
    ::waitpid(pid_, &status, 0);
    pid_ = -1;
  }
  for (int* fd : {&pidfd_, &out_fd_, &wake_pipe_[0], &wake_pipe_[1]}) {
    if (*fd >= 0) ::close(*fd);
    *fd = -1;
  }
  for (auto& [token, result] : pending_) {
    if (!result) result = CommandResult{false, "the phone is stopping"};
  }
  changed_.notify_all();
}

bool Baresip::wait_ready(std::chrono::milliseconds timeout) {
  std::unique_lock lock(mutex_);
  return changed_.wait_for(lock, timeout, [&] { return ready_ || stopping_; }) && ready_;
}

pid_t Baresip::pid() const {
  std::lock_guard lock(mutex_);
  return pid_;
}

int Baresip::restarts() const {
  std::lock_guard lock(mutex_);
  return restarts_;
}

int Baresip::port_changes() const {
  std::lock_guard lock(mutex_);
  return port_changes_;
}

CommandResult Baresip::command(const std::string& name, const std::string& params,
                               std::chrono::milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  std::unique_lock lock(mutex_);
  if (!changed_.wait_until(lock, deadline, [&] { return ready_ || stopping_; }) || !ready_) {
    return {false, "the phone service (baresip) is not running"};
  }
  const std::string token = "m" + std::to_string(next_token_++);
  const std::string frame = encode_netstring(
      nlohmann::json{{"command", name}, {"params", params}, {"token", token}}.dump());
  pending_[token];
  std::size_t sent = 0;
  while (sent < frame.size()) {
    const ssize_t n = ::send(control_fd_, frame.data() + sent, frame.size() - sent, MSG_NOSIGNAL);
    if (n <= 0) {
      pending_.erase(token);
      return {false, "cannot write to baresip's control socket: " +
                         std::string(std::strerror(errno))};
    }
    sent += static_cast<std::size_t>(n);
  }
  changed_.wait_until(lock, deadline, [&] { return pending_[token].has_value(); });
  auto result = pending_[token];
  pending_.erase(token);
  if (!result) return {false, "baresip did not answer the command '" + name + "'"};
  return *result;
}

void Baresip::connect_control() {
  const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_port = htons(static_cast<std::uint16_t>(ctrl_port_));
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (fd < 0 || ::connect(fd, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0) {
    log_phone(LogLevel::kError, "cannot connect to baresip's control port " +
                                    std::to_string(ctrl_port_) + ": " + std::strerror(errno));
    if (fd >= 0) ::close(fd);
    return;
  }
  control_fd_ = fd;
  reader_ = NetstringReader();
  // Ready only once baresip answers on this connection: ctrl_tcp sends events to the
  // connection it has accepted, and a connection still in the kernel's backlog misses
  // them (seen: an incoming call's event lost right after start).
  const std::string probe = encode_netstring(
      nlohmann::json{{"command", "reginfo"}, {"params", ""}, {"token", kProbeToken}}.dump());
  if (::send(fd, probe.data(), probe.size(), MSG_NOSIGNAL) != static_cast<ssize_t>(probe.size())) {
    log_phone(LogLevel::kError, "cannot write to baresip's control port");
  }
}

void Baresip::close_control() {
  if (control_fd_ >= 0) ::close(control_fd_);
  control_fd_ = -1;
  ready_ = false;
  for (auto& [token, result] : pending_) {
    if (!result) result = CommandResult{false, "baresip stopped before it answered"};
  }
  changed_.notify_all();
}

void Baresip::on_child_exit() {
  int status = 0;
  ::waitpid(pid_, &status, 0);
  const bool was_ready = child_was_ready_;
  close_control();
  ::close(pidfd_);
  pidfd_ = -1;
  if (out_fd_ >= 0) ::close(out_fd_);
  out_fd_ = -1;
  const std::string how = WIFSIGNALED(status) ? "killed by signal " + std::to_string(WTERMSIG(status))
                                              : "exited with status " + std::to_string(WEXITSTATUS(status));
  log_phone(LogLevel::kWarning, "baresip (pid " + std::to_string(pid_) + ") " + how +
                                    (was_ready ? "; restarting" : "; output: " + output_tail_));
  pid_ = -1;
  if (!was_ready && new_ports_after_loss(status)) {
    restart_at_ = std::chrono::steady_clock::now();
    return;
  }
  const bool quick_death = !was_ready;
  restart_at_ = std::chrono::steady_clock::now() +
                (quick_death ? std::chrono::milliseconds(1000) : std::chrono::milliseconds(0));
}

bool Baresip::new_ports_after_loss(int status) {
  // Another program took a port between our choice and baresip's bind (seen when two test
  // runs share a machine): the same ports would fail forever, so choose again.
  const bool sip_lost =
      output_tail_.find(kSipPortTaken) != std::string::npos ||
      (WIFEXITED(status) && WEXITSTATUS(status) == kExitAddressInUse);
  const bool ctrl_lost = output_tail_.find(kCtrlPortTaken) != std::string::npos;
  const bool sip_ours = settings_.sip_port == 0;  // a configured port is the user's
  if (!(ctrl_lost || (sip_lost && sip_ours)) || port_retries_left_ <= 0) return false;
  const int old_sip = sip_port_;
  const int old_ctrl = ctrl_port_;
  try {
    if (sip_lost && sip_ours) sip_port_ = choose_port_(true);
    if (ctrl_lost) ctrl_port_ = choose_port_(false);
    write_baresip_config(settings_, sip_port_, ctrl_port_, config_dir_);
  } catch (const std::exception& e) {
    log_phone(LogLevel::kError, std::string("cannot choose new ports: ") + e.what());
    return false;
  }
  --port_retries_left_;
  ++port_changes_;
  std::string what;
  if (sip_lost && sip_ours) {
    what = "SIP port " + std::to_string(old_sip) + " is taken by another program; now port " +
           std::to_string(sip_port_);
  }
  if (ctrl_lost) {
    what += (what.empty() ? "" : "; ") + std::string("control port ") +
            std::to_string(old_ctrl) + " is taken by another program; now port " +
            std::to_string(ctrl_port_);
  }
  log_phone(LogLevel::kWarning,
            what + " (new ports " + std::to_string(kMaxPortRetries - port_retries_left_) +
                " of at most " + std::to_string(kMaxPortRetries) + ")");
  return true;
}

void Baresip::run() {
  std::vector<BaresipEvent> events;
  for (;;) {
    std::vector<pollfd> fds;
    int timeout_ms = -1;
    {
      std::lock_guard lock(mutex_);
      if (stopping_) return;
      if (pid_ < 0 && restart_at_) {
        const auto now = std::chrono::steady_clock::now();
        if (now >= *restart_at_) {
          restart_at_.reset();
          try {
            const bool new_ports = port_changes_ != port_changes_counted_;
            spawn();
            // A child that lost its ports never served anyone: not a restart of the service.
            if (new_ports) {
              port_changes_counted_ = port_changes_;
            } else {
              ++restarts_;
            }
          } catch (const std::exception& e) {
            log_phone(LogLevel::kError, e.what());
            restart_at_ = now + std::chrono::seconds(1);
          }
        }
        if (restart_at_) {
          timeout_ms = static_cast<int>(std::chrono::duration_cast<std::chrono::milliseconds>(
                                            *restart_at_ - now).count()) + 1;
        }
      }
      fds.push_back({wake_pipe_[0], POLLIN, 0});
      fds.push_back({out_fd_, POLLIN, 0});
      fds.push_back({pidfd_, POLLIN, 0});
      fds.push_back({control_fd_, POLLIN, 0});
    }
    if (::poll(fds.data(), fds.size(), timeout_ms) < 0 && errno != EINTR) return;
    char buffer[8192];
    if (fds[0].revents) {
      while (::read(wake_pipe_[0], buffer, sizeof buffer) > 0) {
      }
    }
    std::unique_lock lock(mutex_);
    if (stopping_) return;
    if (fds[1].fd >= 0 && fds[1].revents) {
      const ssize_t n = ::read(out_fd_, buffer, sizeof buffer);
      if (n > 0) {
        output_tail_.append(buffer, static_cast<std::size_t>(n));
        if (!ready_ && ports_lost() && pid_ > 0) {
          // Without its control socket (or SIP) this child is of no use: end it, and
          // on_child_exit chooses new ports.
          ::kill(pid_, SIGKILL);
        }
        if (!ready_ && control_fd_ < 0 && !ports_lost() &&
            output_tail_.find(kReadyBanner) != std::string::npos) {
          connect_control();
          output_tail_.clear();
        }
        if (output_tail_.size() > kTailBytes) output_tail_.erase(0, output_tail_.size() - kTailBytes);
      } else {
        ::close(out_fd_);
        out_fd_ = -1;
      }
    }
    std::string control_bytes;
    if (fds[3].fd >= 0 && fds[3].fd == control_fd_ && fds[3].revents) {
      const ssize_t n = ::recv(control_fd_, buffer, sizeof buffer, 0);
      if (n > 0) {
        control_bytes.assign(buffer, static_cast<std::size_t>(n));
      } else {
        close_control();
      }
    }
    std::string exited;
    if (fds[2].fd >= 0 && fds[2].fd == pidfd_ && fds[2].revents) {
      on_child_exit();
      exited = "baresip died";
    }
    lock.unlock();
    if (!control_bytes.empty()) process_control_bytes(control_bytes);
    if (!exited.empty() && on_event_) on_event_({"MARVIN_EXITED", "marvin", "", "", "", exited});
  }
}

void Baresip::process_control_bytes(std::string_view bytes) {
  reader_.feed(bytes);
  while (auto frame = reader_.next()) {
    if (!frame->error.empty()) {
      log_phone(LogLevel::kWarning, frame->error + " (ignored)");
      continue;
    }
    handle_frame(frame->payload);
  }
}

void Baresip::handle_frame(const std::string& payload) {
  nlohmann::json j = nlohmann::json::parse(payload, nullptr, false);
  if (j.is_discarded() || !j.is_object()) {
    log_phone(LogLevel::kWarning, "control socket: not a JSON object (ignored): " +
                                      payload.substr(0, 200));
    return;
  }
  if (json_true(j, "response")) {
    const std::string token = json_string(j, "token");
    std::unique_lock lock(mutex_);
    if (token == kProbeToken) {
      if (!ready_ && control_fd_ >= 0) {
        ready_ = true;
        child_was_ready_ = true;
        port_retries_left_ = kMaxPortRetries;
        changed_.notify_all();
        lock.unlock();
        if (on_event_) on_event_({"MARVIN_READY", "marvin", "", "", "", ""});
      }
      return;
    }
    auto it = pending_.find(token);
    if (it == pending_.end()) return;  // an answer nobody waits for any more
    it->second = CommandResult{json_true(j, "ok"), json_string(j, "data")};
    changed_.notify_all();
    return;
  }
  if (!json_true(j, "event")) {
    log_phone(LogLevel::kWarning, "control socket: neither an event nor a response (ignored): " +
                                      payload.substr(0, 200));
    return;
  }
  BaresipEvent event{json_string(j, "type"),      json_string(j, "class"),
                     json_string(j, "direction"), json_string(j, "peeruri"),
                     json_string(j, "id"),        json_string(j, "param")};
  if (event.type.empty()) {
    log_phone(LogLevel::kWarning, "control socket: event without a type (ignored): " +
                                      payload.substr(0, 200));
    return;
  }
  log_phone(LogLevel::kDebug, "event " + payload.substr(0, 300));
  if (on_event_) on_event_(event);
}

}  // namespace marvin::telephony
