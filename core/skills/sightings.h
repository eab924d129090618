// Sightings as the Robot API 1.3 serves them (look_around, sightings_find): the host
// records every known person or thing the camera sees, with the room and the furniture
// it is near. The real log is the owner's SQLite store (core/app/store_sightings.h); this
// in-memory one serves `run --in-memory` and the MockRobot. Thread-safe.
#pragma once

#include <algorithm>
#include <cstdint>
#include <functional>
#include <map>
#include <mutex>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "data/sighting.h"

namespace marvin::skills {

class SightingLog {
 public:
  virtual ~SightingLog() = default;
  // Stamps `s` with now and replaces what was recorded for the same what + kind.
  virtual void record(const data::Sighting& s) = 0;
  // Newest first; `what` empty: everything; only those seen at or after `since_utc_ms`.
  virtual std::vector<data::Sighting> find(std::string_view what, std::int64_t since_utc_ms) = 0;
};

class InMemorySightingLog final : public SightingLog {
 public:
  explicit InMemorySightingLog(std::function<std::int64_t()> now_ms) : now_ms_(std::move(now_ms)) {}

  void record(const data::Sighting& s) override {
    if (s.what.empty()) throw std::invalid_argument("sighting: 'what' is empty");
    std::lock_guard lock(mutex_);
    data::Sighting copy = s;
    copy.seen_utc_ms = now_ms_();
    rows_[{lower(s.what), s.kind}] = std::move(copy);
  }
  std::vector<data::Sighting> find(std::string_view what, std::int64_t since_utc_ms) override {
    std::lock_guard lock(mutex_);
    std::vector<data::Sighting> out;
    const std::string want = lower(std::string(what));
    for (const auto& [key, s] : rows_) {
      if ((want.empty() || key.first == want) && s.seen_utc_ms >= since_utc_ms) out.push_back(s);
    }
    std::stable_sort(out.begin(), out.end(), [](const data::Sighting& a, const data::Sighting& b) {
      return a.seen_utc_ms > b.seen_utc_ms;
    });
    return out;
  }

 private:
  static std::string lower(std::string s) {
    for (char& c : s) c = static_cast<char>(c >= 'A' && c <= 'Z' ? c - 'A' + 'a' : c);
    return s;
  }
  std::function<std::int64_t()> now_ms_;
  std::mutex mutex_;
  std::map<std::pair<std::string, std::string>, data::Sighting> rows_;
};

}  // namespace marvin::skills
