// Counters every stream and node keeps while the graph runs, and their snapshots.
//
// Counters are updated on the hot path without locks (each has a single writer: the
// producer or consumer node, which never runs on two threads at once) and may be read at
// any time from any thread through Graph::stats(). Snapshots are plain values.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <string>
#include <vector>

namespace marvin::graph {

// A log-linear histogram of durations in nanoseconds (8 sub-buckets per power of two, so
// quantiles are within 12.5%). One writer, any number of readers.
class LatencyHistogram {
 public:
  void record(int64_t ns) {
    auto& bin = bins_[index_of(ns < 0 ? 0 : static_cast<uint64_t>(ns))];
    bin.store(bin.load(std::memory_order_relaxed) + 1, std::memory_order_relaxed);
  }
  // The q-quantile (0..1) in nanoseconds, upper edge of its bucket; 0 when nothing was recorded.
  int64_t quantile(double q) const;
  uint64_t count() const;

 private:
  static constexpr std::size_t kBins = 8 + 61 * 8;
  static std::size_t index_of(uint64_t v) {
    if (v < 8) return static_cast<std::size_t>(v);
    const int e = 63 - __builtin_clzll(v);
    const uint64_t sub = (v >> (e - 3)) & 7;
    return 8 + static_cast<std::size_t>(e - 3) * 8 + static_cast<std::size_t>(sub);
  }
  static uint64_t upper_edge(std::size_t index);
  std::array<std::atomic<uint64_t>, kBins> bins_{};
};

// A counter with a single writer: cheaper than fetch_add, still safe to read concurrently.
class Counter {
 public:
  void add(uint64_t n = 1) { value_.store(value_.load(std::memory_order_relaxed) + n, std::memory_order_relaxed); }
  void raise_to(uint64_t n) {
    if (n > value_.load(std::memory_order_relaxed)) value_.store(n, std::memory_order_relaxed);
  }
  uint64_t get() const { return value_.load(std::memory_order_relaxed); }

 private:
  std::atomic<uint64_t> value_{0};
};

struct StreamStats {
  std::string name;        // "producer.port -> consumer.port"
  std::string policy;      // "lossless", "drop_oldest", "drop_newest"
  uint64_t capacity = 0;
  uint64_t pushed = 0;     // packets offered by the producer
  uint64_t delivered = 0;  // packets taken by the consumer
  uint64_t dropped = 0;    // packets discarded by a lossy policy
  uint64_t high_water = 0; // largest queue length seen
  // Input latency: from the start of the producer's process() call that emitted a packet
  // to the consumer taking it (queue wait plus the rest of that call).
  int64_t latency_p50_ns = 0;
  int64_t latency_p99_ns = 0;
};

struct NodeStats {
  std::string name;
  std::string type;
  uint64_t process_calls = 0;
  uint64_t emitted = 0;
  int64_t process_p50_ns = 0;
  int64_t process_p99_ns = 0;
};

struct GraphStats {
  std::vector<NodeStats> nodes;
  std::vector<StreamStats> streams;
  uint64_t watchdog_events = 0;

  // A fixed-width table for people (what `marvin graph run` prints).
  std::string to_text() const;
};

}  // namespace marvin::graph
