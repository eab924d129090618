// A program a test starts and talks to: the real `marvin`, `marvin-mcu-sim`, a shell
// command line. Arguments and environment in; stdin written; stdout (and stderr) read as
// it comes, waiting on the pipes (poll) for a pattern with a generous timeout, never by
// sleeping; the exit status at the end. A child still running when the object goes is
// killed (SIGKILL) and reaped, so a failing test leaves no process behind.
//
// Errors (cannot start, stdin closed early, a timeout) throw std::runtime_error naming
// the program and what was awaited, with the output so far; doctest reports the message.
// Not thread-safe: one test thread drives one child.
#pragma once

#include <sys/types.h>

#include <chrono>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace marvin::test_support {

// Long enough for a slow sanitizer build on a busy machine; only reached when a test fails.
inline constexpr std::chrono::seconds kGenerousTimeout{180};

// Where one of a child's standard streams goes.
enum class ChildStream {
  kPipe,     // to/from the ChildProcess (write(), output(), errors())
  kNull,     // /dev/null
  kInherit,  // the test's own
};

struct ChildOptions {
  // "NAME=value" entries, added to the test's environment (replacing a same-named one), or
  // the whole environment when `clean_environment`.
  std::vector<std::string> environment;
  bool clean_environment = false;
  ChildStream in = ChildStream::kPipe;
  ChildStream out = ChildStream::kPipe;
  ChildStream err = ChildStream::kPipe;
  // When set, stderr goes to this file (created or truncated) instead of `err`.
  std::filesystem::path err_file;
  // stdin, stdout and stderr on a new pseudo-terminal (its controlling terminal), read and
  // written through output() and write(); `in`, `out`, `err` are then ignored.
  bool terminal = false;
};

class ChildProcess {
 public:
  using Stream = ChildStream;
  using Options = ChildOptions;

  // Starts argv[0] (a path: no $PATH search) with `argv`.
  explicit ChildProcess(std::vector<std::string> argv, Options options = {});
  // Starts /bin/sh -c `command_line`.
  static ChildProcess shell(const std::string& command_line, Options options = {});

  ChildProcess(ChildProcess&& other) noexcept;
  ChildProcess& operator=(ChildProcess&&) = delete;
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;
  ~ChildProcess();

  pid_t pid() const { return pid_; }

  // Writes `text` to the child's stdin (reading its output meanwhile, so that neither side
  // can block the other on a full pipe).
  void write(std::string_view text, std::chrono::milliseconds timeout = kGenerousTimeout);
  // write(line + "\n").
  void send_line(const std::string& line) { write(line + "\n"); }
  // End of input for the child. No effect on a terminal.
  void close_stdin();

  // Reads stdout until `done(output())` holds: true then; false when the output ends or
  // `timeout` passes first.
  bool read_until(const std::function<bool(const std::string& output)>& done,
                  std::chrono::milliseconds timeout = kGenerousTimeout);

  // The next line of stdout (after those returned before) for which `want` holds; lines
  // before it are passed over. Throws, naming `what` and showing the output so far, when
  // the output ends or `timeout` passes first.
  std::string wait_for_line(const std::string& what,
                            const std::function<bool(const std::string& line)>& want,
                            std::chrono::milliseconds timeout = kGenerousTimeout);
  // The next line equal to `exact`.
  std::string wait_for_line(const std::string& exact);
  // The next line containing `part`.
  std::string wait_for_line_containing(const std::string& part);

  // Closes stdin, reads stdout and stderr to their end, waits for the exit and returns the
  // wait status (WIFEXITED/WEXITSTATUS; see exit_code()). Throws after killing the child
  // when it does not end within `timeout`.
  int finish(std::chrono::milliseconds timeout = kGenerousTimeout);

  // Sends `signal`, then reaps the child as finish() does (SIGKILL if it outlives the
  // timeout). No effect once the child is reaped.
  void stop(int signal, std::chrono::milliseconds timeout = kGenerousTimeout);

  // Everything read from stdout (or the terminal) and from a piped stderr so far.
  const std::string& output() const { return out_text_; }
  const std::string& errors() const { return err_text_; }
  // output() split at newlines (a last line without one included), as std::getline does.
  std::vector<std::string> output_lines() const;

 private:
  ChildProcess() = default;
  void start(std::vector<std::string> argv, const Options& options);
  // Waits up to `ms` for output and reads what is there; false on timeout or when every
  // output stream has ended.
  bool pump(int ms);
  bool outputs_open() const { return out_fd_ >= 0 || err_fd_ >= 0; }
  // Reaps within `timeout`; false (child still running) when it passes.
  bool reap(std::chrono::milliseconds timeout);
  std::string describe() const;

  std::string name_;
  pid_t pid_ = -1;
  int pidfd_ = -1;
  int in_fd_ = -1;
  int out_fd_ = -1;
  int err_fd_ = -1;
  bool terminal_ = false;
  int status_ = -1;
  std::string out_text_;
  std::string err_text_;
  std::size_t next_line_ = 0;  // offset in out_text_ of the first line not yet returned
};

// The exit code in a wait status, -1 when the child did not exit (a signal ended it).
int exit_code(int wait_status);

}  // namespace marvin::test_support
