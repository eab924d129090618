// What the telephony tests share: WAV files (a tone to send, a recording to analyse), an
// event log a test waits on (condition variable, generous timeout), waiting for a file to be
// closed after writing (inotify), and a test peer: a second baresip user agent on 127.0.0.1
// driven over its own control socket.
#pragma once

#include <chrono>
#include <condition_variable>
#include <filesystem>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "telephony/baresip.h"
#include "telephony/phone.h"

namespace marvin::telephony::testing {

inline constexpr std::chrono::seconds kWait{30};  // only reached when a test fails

// 8 kHz mono 16-bit PCM.
void write_tone_wav(const std::filesystem::path& path, double frequency_hz, double seconds);
// Samples of a 16-bit mono WAV and its rate. Throws naming the file when it is not one.
std::vector<double> read_wav(const std::filesystem::path& path, int* rate);
// The strongest frequency between 100 and 3500 Hz, in 20 Hz steps (Goertzel).
double dominant_frequency(const std::vector<double>& samples, int rate);

// Watches `dir` (inotify, from construction on) for files closed after writing.
class ClosedFileWatch {
 public:
  explicit ClosedFileWatch(const std::filesystem::path& dir);
  ~ClosedFileWatch();
  ClosedFileWatch(const ClosedFileWatch&) = delete;
  ClosedFileWatch& operator=(const ClosedFileWatch&) = delete;
  // The next such file whose name ends with `suffix`; nullopt after `timeout`.
  std::optional<std::filesystem::path> wait(const std::string& suffix,
                                            std::chrono::milliseconds timeout);

 private:
  std::filesystem::path dir_;
  int fd_ = -1;
};

// Events from any thread; tests wait for one that matches.
template <typename Event>
class EventLog {
 public:
  void add(const Event& event) {
    std::lock_guard lock(mutex_);
    events_.push_back(event);
    changed_.notify_all();
  }
  // The first event at or after position `*from` that matches; `*from` moves past it.
  std::optional<Event> wait(const std::function<bool(const Event&)>& match, std::size_t* from,
                            std::chrono::milliseconds timeout = kWait) {
    std::unique_lock lock(mutex_);
    std::optional<Event> found;
    changed_.wait_for(lock, timeout, [&] {
      for (; *from < events_.size(); ++*from) {
        if (match(events_[*from])) {
          found = events_[(*from)++];
          return true;
        }
      }
      return false;
    });
    return found;
  }
  std::vector<Event> all() const {
    std::lock_guard lock(mutex_);
    return events_;
  }

 private:
  mutable std::mutex mutex_;
  std::condition_variable changed_;
  std::vector<Event> events_;
};

// A second user agent: answers at once (`auto_answer`) or lets the test decide.
class TestPeer {
 public:
  TestPeer(const std::filesystem::path& dir, bool auto_answer, std::string user = "peer");
  // Where to call it: sip:<user>@127.0.0.1:<its SIP port now>. Its own address (what
  // Marvin sees as the caller) is sip:<user>@127.0.0.1.
  std::string uri() const;
  Baresip& ua() { return ua_; }
  EventLog<BaresipEvent>& events() { return events_; }
  std::optional<BaresipEvent> wait_event(const std::string& type, std::size_t* from) {
    return events_.wait([&](const BaresipEvent& e) { return e.type == type; }, from);
  }
  const std::filesystem::path& record_dir() const { return record_dir_; }

 private:
  std::string user_;
  std::filesystem::path record_dir_;
  EventLog<BaresipEvent> events_;
  Baresip ua_;
};

// Marvin's side: a Phone whose events land in a log.
PhoneSettings marvin_settings(const std::filesystem::path& dir,
                              const std::filesystem::path& audio_in = {});

}  // namespace marvin::telephony::testing
