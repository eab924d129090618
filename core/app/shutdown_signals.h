// SIGINT (Ctrl-C) and SIGTERM (systemd, kill) as a request to stop cleanly. Killed by
// them, Marvin would leave a task half done, a call open and its phone's files in /tmp;
// stopped, it ends the task as "stop" does, hangs up and removes what it made.
//
// The signals are blocked in the thread that constructs this and in every thread started
// after it (threads inherit the mask), so construct it before any other thread starts; one
// thread of its own takes them (sigwait) and calls the handler of on_signal(). A second
// signal while stopping ends the process at once (exit status 128 + signal): the way out
// of a stop that hangs. A child process must not inherit the mask: a forked child unblocks
// the signals before exec (core/telephony/baresip.cpp).
#pragma once

#include <signal.h>

#include <atomic>
#include <condition_variable>
#include <functional>
#include <mutex>
#include <thread>

namespace marvin::app {

class ShutdownSignals {
 public:
  ShutdownSignals();
  ~ShutdownSignals();  // ends its thread; the mask as it was before
  ShutdownSignals(const ShutdownSignals&) = delete;
  ShutdownSignals& operator=(const ShutdownSignals&) = delete;

  // Called once, on the signal thread, with the first signal (at once if it came already).
  // A later call replaces the handler not yet called, after waiting for one being called
  // to return: on_signal({}) before destroying what the handler uses.
  void on_signal(std::function<void(int signal)> handler);
  // The first signal received, 0 if none.
  int received() const { return received_.load(); }

 private:
  void wait_for_signals();

  sigset_t signals_;
  sigset_t previous_mask_;
  std::mutex mutex_;
  std::condition_variable returned_;
  std::function<void(int)> handler_;  // guarded by mutex_
  bool handled_ = false;              // guarded by mutex_: the handler was taken
  bool calling_ = false;              // guarded by mutex_: ... and has not returned yet
  std::atomic<int> received_{0};
  std::atomic<bool> ending_{false};
  std::thread thread_;
};

// "SIGINT", "SIGTERM", else "a signal". Async-signal-safe.
const char* signal_name(int signal);

}  // namespace marvin::app
