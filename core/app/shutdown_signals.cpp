#include "app/shutdown_signals.h"

#include <pthread.h>
#include <unistd.h>

#include <cstring>

namespace marvin::app {

ShutdownSignals::ShutdownSignals() {
  sigemptyset(&signals_);
  sigaddset(&signals_, SIGINT);
  sigaddset(&signals_, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &signals_, &previous_mask_);
  thread_ = std::thread([this] { wait_for_signals(); });
}

ShutdownSignals::~ShutdownSignals() {
  // The thread is woken by a signal of its own; ending_ tells it that this one is not a
  // request to stop.
  ending_.store(true);
  pthread_kill(thread_.native_handle(), SIGTERM);
  thread_.join();
  pthread_sigmask(SIG_SETMASK, &previous_mask_, nullptr);
}

void ShutdownSignals::on_signal(std::function<void(int)> handler) {
  std::unique_lock lock(mutex_);
  returned_.wait(lock, [&] { return !calling_; });
  if (handled_) return;
  const int signal = received_.load();
  if (signal == 0 || !handler) {
    handler_ = std::move(handler);
    return;
  }
  handled_ = true;
  lock.unlock();
  handler(signal);
}

void ShutdownSignals::wait_for_signals() {
  for (;;) {
    int signal = 0;
    if (sigwait(&signals_, &signal) != 0) continue;
    if (ending_.load()) return;
    int expected = 0;
    if (!received_.compare_exchange_strong(expected, signal)) {
      // A second Ctrl-C: the first one's stop hangs, or the user will not wait for it.
      const char* name = signal_name(signal);
      const char* tail = " again: quitting at once\n";
      [[maybe_unused]] auto a = ::write(STDERR_FILENO, "marvin: ", 8);
      [[maybe_unused]] auto b = ::write(STDERR_FILENO, name, std::strlen(name));
      [[maybe_unused]] auto c = ::write(STDERR_FILENO, tail, std::strlen(tail));
      ::_exit(128 + signal);
    }
    std::function<void(int)> handler;
    {
      std::lock_guard lock(mutex_);
      if (!handler_) continue;  // on_signal() calls it when it comes
      handler = std::move(handler_);
      handled_ = true;
      calling_ = true;
    }
    handler(signal);
    {
      std::lock_guard lock(mutex_);
      calling_ = false;
    }
    returned_.notify_all();
  }
}

const char* signal_name(int signal) {
  switch (signal) {
    case SIGINT: return "SIGINT";
    case SIGTERM: return "SIGTERM";
    default: return "a signal";
  }
}

}  // namespace marvin::app
