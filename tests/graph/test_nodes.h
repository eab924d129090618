// Node types and helpers shared by the graph tests.
#pragma once

#include <chrono>
#include <condition_variable>
#include <mutex>
#include <vector>

#include "graph/graph.h"

namespace marvin::graph::testing {

// An int64 packet carrying its own timestamp, so a test can tell which packet arrived.
inline Packet int_at(Timestamp ts) { return Packet::make<int64_t>(int64_t{ts}).at(ts); }

// Collects packets seen on an output (Graph::observe) and lets a test wait for a count.
class Recorder {
 public:
  PacketObserver observer() {
    return [this](const Packet& p) {
      std::lock_guard lock(mutex_);
      packets_.push_back(p);
      changed_.notify_all();
    };
  }
  // Waits (generous timeout, not a timing assertion) until at least n packets were seen.
  bool wait_for_count(std::size_t n) {
    std::unique_lock lock(mutex_);
    return changed_.wait_for(lock, std::chrono::seconds(60), [&] { return packets_.size() >= n; });
  }
  std::vector<Packet> packets() const {
    std::lock_guard lock(mutex_);
    return packets_;
  }
  std::vector<Timestamp> timestamps() const {
    std::vector<Timestamp> out;
    for (const Packet& p : packets()) out.push_back(p.timestamp());
    return out;
  }

 private:
  mutable std::mutex mutex_;
  std::condition_variable changed_;
  std::vector<Packet> packets_;
};

inline GraphOptions quiet_options(int threads = 2) {
  GraphOptions o;
  o.threads = threads;
  o.watchdog_thread = false;
  return o;
}

}  // namespace marvin::graph::testing
