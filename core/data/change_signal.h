// ChangeSignal: tells whoever watches that something was written (the web page's live view
// watches the store's event log this way instead of reading it on a timer).
//
// A watcher is a plain callback run on the writing thread right after the write committed,
// outside the store's lock. It must be quick and must not write to the store or unwatch
// itself (the web server only posts a wake-up to its own thread). After unwatch() returns
// the callback is not running and is never called again, so its owner may go away.
//
// Thread-safe.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <mutex>

namespace marvin::data {

class ChangeSignal {
 public:
  using Watcher = std::function<void()>;

  // Returns a token for unwatch().
  std::uint64_t watch(Watcher watcher) {
    std::lock_guard lock(mutex_);
    watchers_.emplace(++last_token_, std::move(watcher));
    return last_token_;
  }

  // Removes the watcher; waits while it runs on another thread. Unknown tokens: no-op.
  void unwatch(std::uint64_t token) {
    std::lock_guard lock(mutex_);
    watchers_.erase(token);
  }

  // Runs every watcher, in the order they were added.
  void notify() {
    std::lock_guard lock(mutex_);
    for (auto& [token, watcher] : watchers_) watcher();
  }

 private:
  std::mutex mutex_;  // held while watchers run: unwatch() then waits for a running one
  std::uint64_t last_token_ = 0;
  std::map<std::uint64_t, Watcher> watchers_;
};

}  // namespace marvin::data
