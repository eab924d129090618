// Where "now" comes from. The store stamps events with it and the scheduler decides what
// is due with it; tests inject a ManualClock so they are exact without sleeping.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>

namespace marvin::data {

class Clock {
 public:
  virtual ~Clock() = default;
  // Milliseconds since the Unix epoch, UTC. Thread-safe.
  virtual std::int64_t now_utc_ms() const = 0;
};

// The system's wall clock.
class SystemClock final : public Clock {
 public:
  std::int64_t now_utc_ms() const override {
    return std::chrono::duration_cast<std::chrono::milliseconds>(
               std::chrono::system_clock::now().time_since_epoch())
        .count();
  }
  static SystemClock& instance() {
    static SystemClock clock;
    return clock;
  }
};

// A clock that only moves when told to (tests, simulations).
class ManualClock final : public Clock {
 public:
  explicit ManualClock(std::int64_t start_utc_ms = 0) : now_(start_utc_ms) {}
  std::int64_t now_utc_ms() const override { return now_.load(); }
  void set(std::int64_t utc_ms) { now_.store(utc_ms); }
  void advance(std::int64_t ms) { now_.fetch_add(ms); }

 private:
  std::atomic<std::int64_t> now_;
};

}  // namespace marvin::data
