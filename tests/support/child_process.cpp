#include "support/child_process.h"

#include <fcntl.h>
#include <poll.h>
#include <pty.h>
#include <signal.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <limits.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <utility>

extern char** environ;

namespace marvin::test_support {
namespace {

using Clock = std::chrono::steady_clock;

int ms_left(Clock::time_point deadline) {
  const auto left =
      std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()).count();
  return left > 0 ? static_cast<int>(left) : 0;
}

void close_fd(int& fd) {
  if (fd >= 0) ::close(fd);
  fd = -1;
}

// The child's environment: the test's, with `extra` added or replacing same-named entries.
std::vector<std::string> environment_for(const ChildProcess::Options& options) {
  std::vector<std::string> env;
  if (!options.clean_environment) {
    for (char** e = environ; *e != nullptr; ++e) {
      const std::string entry = *e;
      const std::string name = entry.substr(0, entry.find('=') + 1);
      bool replaced = false;
      for (const std::string& x : options.environment) replaced |= x.rfind(name, 0) == 0;
      if (!replaced) env.push_back(entry);
    }
  }
  env.insert(env.end(), options.environment.begin(), options.environment.end());
  return env;
}

// Signals stay blocked from before fork until the child has reset every handler: the test
// framework's handlers (and our SIG_IGN for SIGPIPE) must not run in, or be inherited by,
// the child, even when a signal comes before exec.
class SignalsBlocked {
 public:
  SignalsBlocked() {
    sigset_t all;
    ::sigfillset(&all);
    ::pthread_sigmask(SIG_SETMASK, &all, &saved_);
  }
  ~SignalsBlocked() { ::pthread_sigmask(SIG_SETMASK, &saved_, nullptr); }
  SignalsBlocked(const SignalsBlocked&) = delete;
  SignalsBlocked& operator=(const SignalsBlocked&) = delete;
  const sigset_t& saved() const { return saved_; }

 private:
  sigset_t saved_;
};

// In the child, between fork and exec: async-signal-safe calls only.
[[noreturn]] void exec_child(int in, int out, int err, const char* err_file,
                             ChildProcess::Stream err_mode, char* const* argv, char* const* envp,
                             const sigset_t& mask) {
  struct sigaction default_action {};
  default_action.sa_handler = SIG_DFL;
  for (int sig = 1; sig < NSIG; ++sig) ::sigaction(sig, &default_action, nullptr);
  ::sigprocmask(SIG_SETMASK, &mask, nullptr);
  if (in >= 0) ::dup2(in, 0);
  if (out >= 0) ::dup2(out, 1);
  if (err_file != nullptr) {
    const int fd = ::open(err_file, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd >= 0) ::dup2(fd, 2);
  } else if (err >= 0) {
    ::dup2(err, 2);
  } else if (err_mode == ChildProcess::Stream::kNull) {
    const int fd = ::open("/dev/null", O_WRONLY | O_CLOEXEC);
    if (fd >= 0) ::dup2(fd, 2);
  }
  ::execve(argv[0], argv, envp);
  ::_exit(127);
}

}  // namespace

int exit_code(int wait_status) {
  return WIFEXITED(wait_status) ? WEXITSTATUS(wait_status) : -1;
}

ChildProcess::ChildProcess(std::vector<std::string> argv, Options options) {
  start(std::move(argv), options);
}

ChildProcess ChildProcess::shell(const std::string& command_line, Options options) {
  ChildProcess child;
  child.start({"/bin/sh", "-c", command_line}, options);
  return child;
}

ChildProcess::ChildProcess(ChildProcess&& other) noexcept
    : name_(std::move(other.name_)),
      pid_(std::exchange(other.pid_, -1)),
      pidfd_(std::exchange(other.pidfd_, -1)),
      in_fd_(std::exchange(other.in_fd_, -1)),
      out_fd_(std::exchange(other.out_fd_, -1)),
      err_fd_(std::exchange(other.err_fd_, -1)),
      terminal_(other.terminal_),
      status_(other.status_),
      out_text_(std::move(other.out_text_)),
      err_text_(std::move(other.err_text_)),
      next_line_(other.next_line_) {}

ChildProcess::~ChildProcess() {
  close_fd(in_fd_);
  if (pid_ > 0) {
    ::kill(pid_, SIGKILL);
    int status = 0;
    ::waitpid(pid_, &status, 0);
  }
  close_fd(out_fd_);
  close_fd(err_fd_);
  close_fd(pidfd_);
}

void ChildProcess::start(std::vector<std::string> argv, const Options& options) {
  if (argv.empty()) throw std::runtime_error("ChildProcess: argv is empty (expected a program)");
  name_ = argv[0];
  if (argv[0] == "/bin/sh" && argv.size() == 3) name_ = "sh -c \"" + argv[2] + "\"";
  // A child that exits early must fail our write() with EPIPE, not end the test run.
  ::signal(SIGPIPE, SIG_IGN);

  // Everything the child needs is made before fork: after it, only async-signal-safe calls.
  const std::vector<std::string> env = environment_for(options);
  std::vector<char*> argv_p, envp;
  for (std::string& a : argv) argv_p.push_back(a.data());
  argv_p.push_back(nullptr);
  for (const std::string& e : env) envp.push_back(const_cast<char*>(e.c_str()));
  envp.push_back(nullptr);
  const std::string err_file = options.err_file.string();
  const char* err_file_p = err_file.empty() ? nullptr : err_file.c_str();

  terminal_ = options.terminal;
  if (terminal_) {
    int master = -1;
    {
      SignalsBlocked blocked;
      pid_ = ::forkpty(&master, nullptr, nullptr, nullptr);
      if (pid_ == 0) {
        exec_child(-1, -1, -1, nullptr, Stream::kInherit, argv_p.data(), envp.data(),
                   blocked.saved());
      }
    }
    if (pid_ < 0) throw std::runtime_error(name_ + ": forkpty failed: " + std::strerror(errno));
    ::fcntl(master, F_SETFD, FD_CLOEXEC);
    in_fd_ = master;
    out_fd_ = ::dup(master);
    ::fcntl(out_fd_, F_SETFD, FD_CLOEXEC);
  } else {
    // [0] is the child's end of each stream, [1] ours; -1 where there is none.
    int in[2] = {-1, -1}, out[2] = {-1, -1}, err[2] = {-1, -1};
    auto open_stream = [&](Stream mode, int (&p)[2], bool child_reads) {
      if (mode == Stream::kPipe) {
        if (::pipe2(p, O_CLOEXEC) != 0) {
          throw std::runtime_error(name_ + ": pipe2 failed: " + std::strerror(errno));
        }
        if (!child_reads) std::swap(p[0], p[1]);  // p[0]: child's write end
      } else if (mode == Stream::kNull) {
        p[0] = ::open("/dev/null", (child_reads ? O_RDONLY : O_WRONLY) | O_CLOEXEC);
      }
    };
    open_stream(options.in, in, true);
    open_stream(options.out, out, false);
    if (err_file_p == nullptr && options.err == Stream::kPipe) open_stream(options.err, err, false);
    {
      SignalsBlocked blocked;
      pid_ = ::fork();
      if (pid_ == 0) {
        exec_child(in[0], out[0], err[0], err_file_p, options.err, argv_p.data(), envp.data(),
                   blocked.saved());
      }
    }
    close_fd(in[0]);
    close_fd(out[0]);
    close_fd(err[0]);
    in_fd_ = in[1];
    out_fd_ = out[1];
    err_fd_ = err[1];
    if (pid_ < 0) throw std::runtime_error(name_ + ": fork failed: " + std::strerror(errno));
  }
  // A descriptor that polls readable once the child has exited (glibc's pidfd_open wrapper is
  // not declared for C++ in Debian 12's headers). -1 on an old kernel: reap() then waits
  // without a bound.
  pidfd_ = static_cast<int>(::syscall(SYS_pidfd_open, pid_, 0));
}

void ChildProcess::write(std::string_view text, std::chrono::milliseconds timeout) {
  if (in_fd_ < 0) throw std::runtime_error(name_ + ": write after stdin was closed");
  const auto deadline = Clock::now() + timeout;
  while (!text.empty()) {
    pollfd fds[3] = {{in_fd_, POLLOUT, 0}, {out_fd_, POLLIN, 0}, {err_fd_, POLLIN, 0}};
    const int ready = ::poll(fds, 3, ms_left(deadline));
    if (ready < 0 && errno == EINTR) continue;
    if (ready <= 0) {
      throw std::runtime_error(name_ + ": its stdin took no input for " +
                               std::to_string(timeout.count()) + " ms" + describe());
    }
    if ((fds[1].revents | fds[2].revents) != 0) pump(0);
    if ((fds[0].revents & (POLLOUT | POLLERR | POLLHUP)) != 0) {
      // At most PIPE_BUF bytes: POLLOUT promises that much room, so this write never blocks.
      const ssize_t n = ::write(in_fd_, text.data(), std::min<std::size_t>(text.size(), PIPE_BUF));
      if (n < 0 && errno == EINTR) continue;
      if (n < 0) {
        throw std::runtime_error(name_ + ": cannot write to its stdin: " +
                                 std::strerror(errno) + describe());
      }
      text.remove_prefix(static_cast<std::size_t>(n));
    }
  }
}

void ChildProcess::close_stdin() {
  if (!terminal_) close_fd(in_fd_);
}

bool ChildProcess::pump(int ms) {
  if (!outputs_open()) return false;
  pollfd fds[2] = {{out_fd_, POLLIN, 0}, {err_fd_, POLLIN, 0}};
  int ready = ::poll(fds, 2, ms);
  if (ready < 0 && errno == EINTR) return true;
  if (ready <= 0) return false;
  char buffer[4096];
  auto drain = [&](pollfd& p, int& fd, std::string& text) {
    if (fd < 0 || p.revents == 0) return;
    const ssize_t n = ::read(fd, buffer, sizeof buffer);
    if (n > 0) {
      text.append(buffer, static_cast<std::size_t>(n));
    } else if (n == 0 || errno != EINTR) {
      close_fd(fd);  // end of output (a terminal says EIO once the child has gone)
    }
  };
  drain(fds[0], out_fd_, out_text_);
  drain(fds[1], err_fd_, err_text_);
  return true;
}

bool ChildProcess::read_until(const std::function<bool(const std::string&)>& done,
                              std::chrono::milliseconds timeout) {
  const auto deadline = Clock::now() + timeout;
  for (;;) {
    if (done(out_text_)) return true;
    if (out_fd_ < 0 || ms_left(deadline) == 0) return false;
    pump(ms_left(deadline));
  }
}

std::string ChildProcess::wait_for_line(const std::string& what,
                                        const std::function<bool(const std::string&)>& want,
                                        std::chrono::milliseconds timeout) {
  const auto deadline = Clock::now() + timeout;
  for (;;) {
    for (std::size_t nl; (nl = out_text_.find('\n', next_line_)) != std::string::npos;) {
      std::string line = out_text_.substr(next_line_, nl - next_line_);
      next_line_ = nl + 1;
      if (want(line)) return line;
    }
    if (out_fd_ < 0 || ms_left(deadline) == 0) {
      throw std::runtime_error(name_ + ": no line " + what +
                               (out_fd_ < 0 ? " before the output ended"
                                            : " within " + std::to_string(timeout.count()) +
                                                  " ms") +
                               describe());
    }
    pump(ms_left(deadline));
  }
}

std::string ChildProcess::wait_for_line(const std::string& exact) {
  return wait_for_line("\"" + exact + "\"", [&](const std::string& l) { return l == exact; });
}

std::string ChildProcess::wait_for_line_containing(const std::string& part) {
  return wait_for_line("containing \"" + part + "\"",
                       [&](const std::string& l) { return l.find(part) != std::string::npos; });
}

bool ChildProcess::reap(std::chrono::milliseconds timeout) {
  if (pid_ <= 0) return true;
  if (pidfd_ >= 0) {
    pollfd p{pidfd_, POLLIN, 0};  // readable once the child has exited
    int ready = 0;
    const auto deadline = Clock::now() + timeout;
    while ((ready = ::poll(&p, 1, ms_left(deadline))) < 0 && errno == EINTR) {
    }
    if (ready == 0) return false;
  }
  int status = 0;
  while (::waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
  }
  status_ = status;
  pid_ = -1;
  close_fd(pidfd_);
  return true;
}

int ChildProcess::finish(std::chrono::milliseconds timeout) {
  const auto deadline = Clock::now() + timeout;
  close_stdin();
  while (outputs_open() && ms_left(deadline) > 0) pump(ms_left(deadline));
  if (!reap(std::chrono::milliseconds(ms_left(deadline)))) {
    ::kill(pid_, SIGKILL);
    reap(kGenerousTimeout);
    throw std::runtime_error(name_ + ": did not end within " + std::to_string(timeout.count()) +
                             " ms (killed)" + describe());
  }
  close_fd(in_fd_);
  close_fd(out_fd_);
  close_fd(err_fd_);
  return status_;
}

void ChildProcess::stop(int signal, std::chrono::milliseconds timeout) {
  if (pid_ <= 0) return;
  ::kill(pid_, signal);
  finish(timeout);
}

std::vector<std::string> ChildProcess::output_lines() const {
  std::vector<std::string> lines;
  std::size_t start = 0;
  for (std::size_t nl; (nl = out_text_.find('\n', start)) != std::string::npos; start = nl + 1) {
    lines.push_back(out_text_.substr(start, nl - start));
  }
  if (start < out_text_.size()) lines.push_back(out_text_.substr(start));
  return lines;
}

std::string ChildProcess::describe() const {
  return "; output so far:\n" + out_text_ + (err_text_.empty() ? "" : "stderr:\n" + err_text_);
}

}  // namespace marvin::test_support
