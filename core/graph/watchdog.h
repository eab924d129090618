// Watchdog: notices streams and nodes that stall, lag, or run too fast or too slow.
//
// What to watch is data (a WatchSpec per stream or node in the graph JSON):
//
//   "watchdog": {"deadline_ms": 200, "max_latency_ms": 50, "min_rate_hz": 40,
//                "max_rate_hz": 60, "rate_window_ms": 1000}
//
// For a stream, activity is a packet pushed by the producer and latency is the time a packet
// waited in the queue; for a node, activity is a process() call and latency its duration.
//
//   deadline       more than deadline_ms without activity: one event per silent deadline
//   latency        a packet/call took longer than max_latency_ms
//   rate           activity per second over each rate window outside [min_rate, max_rate]
//   drops          a lossy stream dropped more than its max_consecutive_drops in a row
//
// The hot path only bumps counters in a WatchPoint. The watchdog's own thread wakes every
// check interval, compares counters with the specs, and emits WatchdogEvents to its sink
// (the graph logs them and publishes them on "WatchdogEvents" nodes). Violations that happen
// many times between two checks (latency, drops) are reported once, with `count_since_last`
// saying how many occurred since the previous event of that kind and `total` how many since
// the start. Time comes from an injectable Clock, and check() may be called directly, so
// tests are exact without sleeping.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "graph/clock.h"
#include "graph/packet.h"

namespace marvin::graph {

// Zero means "not watched" for every field.
struct WatchSpec {
  int64_t deadline_ns = 0;
  int64_t max_latency_ns = 0;
  double min_rate_hz = 0;
  double max_rate_hz = 0;
  int64_t rate_window_ns = 1'000'000'000;

  bool watches_anything() const {
    return deadline_ns > 0 || max_latency_ns > 0 || min_rate_hz > 0 || max_rate_hz > 0;
  }
};

// Counters a stream or node updates on its hot path; the watchdog reads them. Single writer
// per field (the producer writes activity, the consumer writes latency violations).
struct WatchPoint {
  int64_t max_latency_ns = 0;  // copied from the spec, read by the hot path
  std::atomic<int64_t> last_activity_ns{INT64_MIN};
  std::atomic<uint64_t> activity{0};
  std::atomic<uint64_t> latency_violations{0};
  std::atomic<uint64_t> drop_violations{0};
  std::atomic<bool> finished{false};  // a finished subject is no longer expected to be active

  void record_activity(int64_t now_ns) {
    last_activity_ns.store(now_ns, std::memory_order_relaxed);
    activity.store(activity.load(std::memory_order_relaxed) + 1, std::memory_order_relaxed);
  }
  void record_latency(int64_t latency_ns) {
    if (max_latency_ns > 0 && latency_ns > max_latency_ns) {
      latency_violations.store(latency_violations.load(std::memory_order_relaxed) + 1,
                               std::memory_order_relaxed);
    }
  }
};

enum class WatchdogEventKind { kDeadline, kLatency, kRateLow, kRateHigh, kDrops };

// "deadline", "latency", "rate_low", "rate_high", "drops".
const char* to_string(WatchdogEventKind kind);

struct WatchdogEvent {
  WatchdogEventKind kind = WatchdogEventKind::kDeadline;
  std::string subject;            // "stream mic.out -> agg.in" or "node agg"
  int64_t time_ns = 0;            // clock reading when detected
  uint64_t total = 0;             // violations of this kind for this subject so far
  uint64_t count_since_last = 0;  // violations since the previous event of this kind
  std::string message;            // one human-readable line with the figures
};

class Watchdog {
 public:
  using EventSink = std::function<void(const WatchdogEvent&)>;

  // `clock` must outlive the watchdog. `sink` is called from the thread running check().
  Watchdog(const Clock& clock, EventSink sink);
  ~Watchdog();
  Watchdog(const Watchdog&) = delete;
  Watchdog& operator=(const Watchdog&) = delete;

  // Watches `point` (owned by the caller, must outlive the watchdog) under `spec`.
  // `subject` names it in events. Call before start(); not thread-safe with check().
  void watch(std::string subject, const WatchSpec& spec, WatchPoint* point);

  // Marks now as the start of observation (deadlines and rate windows count from here).
  void arm();

  // Evaluates every spec against the clock now and emits the events due. Thread-safe.
  void check();

  // Runs check() every `interval` (real time) on a thread of its own until stop().
  void start(std::chrono::milliseconds interval);
  void stop();

  // Events emitted so far.
  uint64_t event_count() const { return events_.load(std::memory_order_relaxed); }

 private:
  struct Watched {
    std::string subject;
    WatchSpec spec;
    WatchPoint* point;
    int64_t quiet_since_ns = 0;  // last activity or last deadline event
    uint64_t deadline_total = 0;
    uint64_t latency_reported = 0, drops_reported = 0;
    uint64_t rate_low_total = 0, rate_high_total = 0;
    int64_t window_start_ns = 0;
    uint64_t window_start_activity = 0;
  };
  void emit(WatchdogEventKind kind, const Watched& w, int64_t now, uint64_t total,
            uint64_t since_last, std::string message);

  const Clock& clock_;
  EventSink sink_;
  std::vector<Watched> watched_;
  std::mutex check_mutex_;
  std::atomic<uint64_t> events_{0};

  std::mutex thread_mutex_;
  std::condition_variable wake_;
  bool stopping_ = false;
  std::thread thread_;
};

}  // namespace marvin::graph

MARVIN_PACKET_TYPE(marvin::graph::WatchdogEvent, "WatchdogEvent");
