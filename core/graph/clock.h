// Clock: where the graph reads time for latencies, rates and watchdog deadlines.
//
// The graph, its streams and its watchdog read time only through a Clock, so tests inject a
// FakeClock and get exact results without sleeping. Readings are nanoseconds on a monotonic
// scale with an arbitrary origin. Thread-safe.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>

namespace marvin::graph {

class Clock {
 public:
  virtual ~Clock() = default;
  virtual int64_t now_ns() const = 0;
};

// std::chrono::steady_clock. Use instance(); it lives for the whole program.
class SteadyClock final : public Clock {
 public:
  static const SteadyClock& instance() {
    static const SteadyClock clock;
    return clock;
  }
  int64_t now_ns() const override {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(
               std::chrono::steady_clock::now().time_since_epoch())
        .count();
  }
};

// A clock that only moves when told to. Starts at `start_ns`.
class FakeClock final : public Clock {
 public:
  explicit FakeClock(int64_t start_ns = 0) : now_(start_ns) {}
  int64_t now_ns() const override { return now_.load(std::memory_order_acquire); }
  void advance_ns(int64_t delta) { now_.fetch_add(delta, std::memory_order_acq_rel); }
  void advance_ms(int64_t delta) { advance_ns(delta * 1'000'000); }
  void set_ns(int64_t value) { now_.store(value, std::memory_order_release); }

 private:
  std::atomic<int64_t> now_;
};

}  // namespace marvin::graph
