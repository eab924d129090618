// What an open page shows live: the status light, what Marvin is doing and the last
// conversation turns, taken from the host's console transcript.
//
// The host already writes everything it does as console lines ("Marvin: ...", "You: ...",
// "[light: executing]", "[move forward, speed 120, 1500 ms]"); the feed reads those lines
// instead of adding a second set of hooks to the host, so the page shows exactly what the
// console shows. New events (alerts, missed reminders, skill errors) come from the event log
// in the store (WebServer polls it), not from here.
//
// Thread-safe: console_line() is called on whichever thread wrote the line; the listener is
// called on that thread too, outside the feed's lock.
#pragma once

#include <deque>
#include <functional>
#include <mutex>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

namespace marvin::web {

class LiveFeed {
 public:
  // How many conversation turns snapshot() keeps.
  static constexpr std::size_t kTurns = 20;

  // One console line of the host.
  void console_line(std::string_view line);

  // {"light": "awaiting", "doing": "move forward, ...", "turns": [{"who","text"}, ...]}
  nlohmann::json snapshot() const;

  // Told each change: ("status", {"light","doing"}) or ("turn", {"who","text"}). One
  // listener (the web server); empty to stop. After set_listener() returns, the previous
  // listener is no longer running and is not called again.
  using Listener = std::function<void(const std::string& kind, const nlohmann::json& data)>;
  void set_listener(Listener listener);

 private:
  mutable std::mutex mutex_;
  std::string light_ = "off";
  std::string doing_;
  std::deque<nlohmann::json> turns_;
  Listener listener_;
  std::mutex listener_mutex_;  // held while the listener runs, so set_listener() can wait
};

}  // namespace marvin::web
