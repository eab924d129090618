// The HC-SR04 sonar on its sweep servo: sweep control and a filtered latest scan.
#pragma once

#include <chrono>
#include <cstdint>
#include <map>
#include <mutex>
#include <vector>

#include "devices/body.h"
#include "devices/serial_link.h"

namespace marvin::devices {

// Median of the last `window` values: a single wild echo (a missed or multipath reading)
// never moves it, a real change moves it after window/2 + 1 readings. No allocation after
// construction.
class MedianFilter {
 public:
  explicit MedianFilter(std::size_t window = 5);
  // Adds a value and returns the median of the values held (the lower middle one when even).
  int add(int value);
  int median() const;
  std::size_t size() const { return count_; }

 private:
  std::vector<int> ring_;
  mutable std::vector<int> scratch_;
  std::size_t next_ = 0, count_ = 0;
};

struct SweepSettings {
  int from_deg = 0;   // 0..120, 0 = straight ahead
  int to_deg = 60;    // from..120
  int step_deg = 15;  // 1..60
};

// Thread-safe. Subscribes to the link's sonar readings for its lifetime.
class SonarScanner {
 public:
  explicit SonarScanner(SerialLink& link, std::size_t median_window = 5,
                        std::chrono::milliseconds max_age = std::chrono::milliseconds(3000));
  ~SonarScanner();
  SonarScanner(const SonarScanner&) = delete;
  SonarScanner& operator=(const SonarScanner&) = delete;

  // Sends the sweep settings (throws std::invalid_argument naming the field if out of
  // range); remembered and sent again by resend() after a reconnect.
  void sweep(const SweepSettings& settings);
  void resend();

  // One point per angle read within max_age of now, filtered, ordered by angle.
  std::vector<ScanPoint> latest_scan() const;
  std::vector<ScanPoint> latest_scan(std::int64_t now_ms) const;
  // Feeds one reading (the link's callback does this; public for tests).
  void add(const SonarReading& reading);
  // The body turns: every reading so far points elsewhere. A median mixing them with the
  // next ones would put a wall seen during the turn straight ahead (a host or MCU that
  // paused mid-turn, so that no new reading came for a while, did that: the robot gave up
  // "something is in the way" in an empty hall). Each angle starts again from its next
  // reading; until then the scan has no point for it.
  void forget_readings();

 private:
  struct Track {
    MedianFilter filter;
    std::int64_t time_ms;
  };
  SerialLink& link_;
  const std::size_t window_;
  const std::chrono::milliseconds max_age_;
  mutable std::mutex mu_;
  SweepSettings settings_;
  std::map<int, Track> tracks_;
  int callback_ = 0;
};

}  // namespace marvin::devices
