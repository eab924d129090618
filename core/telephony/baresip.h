// Supervises one baresip user agent: writes its configuration, starts it as a child
// process, talks to it over ctrl_tcp (netstring-framed JSON), restarts it when it dies and
// stops it when this object goes.
//
// One supervisor thread owns the child and the control socket: it waits (poll) on the
// child's output, the child's exit (pidfd), the socket and a wake-up pipe. baresip
// announces "baresip is ready." on stdout; only then is the control socket connected, so
// nothing waits by sleeping. When the child dies it is restarted at once (a child that
// dies before it was ready is restarted after a second, so a broken configuration does not
// spin). Ports it chose itself (sip_port 0, and always the control port) are chosen again
// when the child could not bind them because another program took them between the choice
// and the start ("Address already in use"): at most kMaxPortRetries times in a row, each
// logged. Events are handed to the handler on the supervisor thread; malformed frames and
// JSON are logged (component "phone") and ignored. The child gets SIGTERM from the kernel
// when the supervisor thread ends without stop() (Marvin killed): no baresip outlives us.
#pragma once

#include <sys/types.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <thread>

#include "telephony/baresip_config.h"
#include "telephony/netstring.h"

namespace marvin::telephony {

// One event from baresip's ctrl_tcp ("CALL_RINGING", "CALL_CLOSED", "REGISTER_FAIL", ...)
// or from the supervisor itself ("MARVIN_READY" after each (re)start, "MARVIN_EXITED"
// when the child died, with its status in `param`).
struct BaresipEvent {
  std::string type;
  std::string event_class;  // "call", "register", "application", "other", "marvin"
  std::string direction;    // "incoming" / "outgoing" for calls
  std::string peer_uri;
  std::string call_id;
  std::string param;
};

struct CommandResult {
  bool ok = false;
  std::string data;  // baresip's answer, or why the command could not be sent
};

class Baresip {
 public:
  using EventHandler = std::function<void(const BaresipEvent&)>;
  // Picks a free 127.0.0.1 port; `pair`: port+1 free as well (pick_free_port by default).
  using PortChooser = std::function<int(bool pair)>;
  // How many times in a row a child that lost its ports gets new ones before the
  // supervisor falls back to restarting it on the same ports every second.
  static constexpr int kMaxPortRetries = 5;

  // `config_dir` is created and owned by this object (config, accounts).
  Baresip(PhoneSettings settings, std::filesystem::path config_dir, EventHandler on_event);
  ~Baresip();
  Baresip(const Baresip&) = delete;
  Baresip& operator=(const Baresip&) = delete;

  // Writes the configuration and starts the child and the supervisor thread. Throws when
  // the configuration is wrong or baresip cannot be started.
  void start();
  // Stops supervising and ends the child (SIGTERM, then SIGKILL). Idempotent.
  void stop();
  // Replaces how ports are chosen (tests: hand out a port that is taken). Before start().
  void set_port_chooser(PortChooser chooser) { choose_port_ = std::move(chooser); }

  // Waits until the control socket is connected (at most `timeout`).
  bool wait_ready(std::chrono::milliseconds timeout);
  // Sends one ctrl_tcp command ("dial", "accept", "hangup", ...) and waits for its answer.
  // Not ready within `timeout`, or no answer: ok=false with the reason in `data`.
  CommandResult command(const std::string& name, const std::string& params = {},
                        std::chrono::milliseconds timeout = std::chrono::seconds(5));

  pid_t pid() const;
  // The ports of the current child: they change when a chosen port was taken.
  int sip_port() const { return sip_port_; }
  int ctrl_port() const { return ctrl_port_; }
  int restarts() const;
  // How many times new ports were chosen because the child could not bind its own.
  int port_changes() const;
  const PhoneSettings& settings() const { return settings_; }

  // Parses bytes as they come from the control socket and dispatches what they hold. Used
  // by the supervisor thread; public so that tests can feed malformed input.
  void process_control_bytes(std::string_view bytes);

 private:
  void run();
  void choose_ports();   // and writes the configuration with them
  bool ports_lost() const;  // the child's output says a port was taken
  // After a child that was never ready exited: when it lost a port we chose, choose new
  // ones (and rewrite the configuration). False: restart as before.
  bool new_ports_after_loss(int status);
  void spawn();          // supervisor thread only: a new child
  void on_child_exit();  // supervisor thread
  void connect_control();
  void close_control();
  void handle_frame(const std::string& payload);
  void wake();

  const PhoneSettings settings_;
  const std::filesystem::path config_dir_;
  const EventHandler on_event_;
  PortChooser choose_port_ = pick_free_port;
  std::atomic<int> sip_port_{0};
  std::atomic<int> ctrl_port_{0};

  mutable std::mutex mutex_;
  std::condition_variable changed_;
  pid_t pid_ = -1;
  int pidfd_ = -1;
  int out_fd_ = -1;
  int control_fd_ = -1;
  bool ready_ = false;
  bool child_was_ready_ = false;  // the current child got as far as "baresip is ready."
  bool stopping_ = false;
  int restarts_ = 0;
  int port_changes_ = 0;
  int port_changes_counted_ = 0;  // port_changes_ when the last child was spawned
  int port_retries_left_ = kMaxPortRetries;  // reset when a child gets as far as ready
  std::uint64_t next_token_ = 1;
  std::map<std::string, std::optional<CommandResult>> pending_;
  std::chrono::steady_clock::time_point started_at_;
  std::optional<std::chrono::steady_clock::time_point> restart_at_;
  std::string output_tail_;  // the child's latest output, for error messages

  NetstringReader reader_;
  int wake_pipe_[2] = {-1, -1};
  std::thread thread_;
};

}  // namespace marvin::telephony
