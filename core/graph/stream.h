// Stream: the bounded queue that carries packets from one output port to one input port.
//
// An output port feeds any number of streams (fan-out); each has its own policy:
//
//   lossless     never drops. When `capacity` packets are queued the producer node is not
//                run again until the consumer takes one (the producer "waits" without
//                blocking a thread). One process() call may emit several packets, so the
//                queue can exceed capacity by what a single call emits; the high-water
//                counter shows it.
//   drop_oldest  when full, the oldest queued packet is discarded to make room.
//   drop_newest  when full, the incoming packet is discarded.
//
// Every drop is counted. The next packet the consumer receives after a drop is flagged
// discontinuous. A lossy stream counts a violation for the watchdog each time a run of
// consecutive drops (drops with no packet taken by the consumer in between) exceeds
// `max_consecutive_drops`.
//
// Besides packets a stream carries a timestamp *bound*: no packet with a smaller timestamp
// will arrive any more. It rises with each packet (to its timestamp + 1) and when the producer
// says so without emitting (a closed latch), and becomes kTimestampDone when the producer
// finishes. Consumers with several inputs use bounds to know an input is "settled" at a
// timestamp even though it carries nothing there.
//
// Thread-safe: one producer thread and one consumer thread at a time (the graph guarantees
// it; each side is a node that never runs on two threads at once).
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <mutex>
#include <string>
#include <vector>

#include "graph/clock.h"
#include "graph/packet.h"
#include "graph/stats.h"
#include "graph/watchdog.h"

namespace marvin::graph {

enum class StreamPolicy { kLossless, kDropOldest, kDropNewest };

// "lossless", "drop_oldest", "drop_newest".
const char* to_string(StreamPolicy policy);

struct StreamOptions {
  StreamPolicy policy = StreamPolicy::kLossless;
  // Queued packets before the policy applies. At least 1.
  std::size_t capacity = 64;
  // Lossy streams: longest run of drops tolerated before the watchdog hears of it. 0 = no limit.
  uint32_t max_consecutive_drops = 0;
  // Marks the stream that closes a cycle. Its packets bypass timestamp synchronisation.
  bool back_edge = false;
};

// Something the stream wakes when the other side may be able to make progress.
class Wakeable {
 public:
  virtual void wake() = 0;

 protected:
  virtual ~Wakeable() = default;
};

class Stream {
 public:
  // `clock` must outlive the stream; it stamps queue entry for latency counters.
  Stream(std::string name, StreamOptions options, const Clock& clock);
  Stream(const Stream&) = delete;
  Stream& operator=(const Stream&) = delete;

  // Who to wake: the consumer when a packet or bound arrives, the producer when a full
  // lossless queue gets room. Either may be null. Call before use.
  void connect(Wakeable* producer, Wakeable* consumer);

  const std::string& name() const { return name_; }
  const StreamOptions& options() const { return options_; }

  // ---- producer side ----

  // Queues `packet` (timestamp already checked by the caller) applying the policy. Returns
  // false if the packet itself was dropped (drop_newest).
  bool push(Packet packet) { return push(std::move(packet), clock_.now_ns()); }
  // Same, with the current clock reading supplied by the caller (saves reading the clock).
  bool push(Packet packet, int64_t now_ns);
  // True when a lossless stream holds `capacity` or more packets. Lock-free.
  bool full() const {
    return options_.policy == StreamPolicy::kLossless &&
           size_.load(std::memory_order_acquire) >= options_.capacity;
  }
  // Raises the bound to `next` (never lowers it) and wakes the consumer if it rose.
  void advance_bound(Timestamp next);
  // The producer is done: the bound becomes kTimestampDone.
  void close() { advance_bound(kTimestampDone); }

  // ---- consumer side ----

  struct Head {
    bool has_packet = false;
    Timestamp front = kTimestampDone;  // timestamp of the first queued packet
    Timestamp bound = kTimestampMin;
    // Smallest timestamp that may still arrive on this stream.
    Timestamp next_possible() const { return has_packet ? front : bound; }
    bool done() const { return !has_packet && bound == kTimestampDone; }
  };
  Head head() const;
  // Takes the first queued packet (empty packet if there is none).
  Packet take() { return take(clock_.now_ns()); }
  Packet take(int64_t now_ns);
  // head() and, if there is a packet, take() under one lock: `out` receives the packet.
  Head poll(Packet& out, int64_t now_ns);
  // Discards everything queued (graph cancellation).
  void clear();

  // ---- observation ----
  StreamStats stats() const;
  WatchPoint& watch_point() { return watch_; }

 private:
  struct Entry {
    Packet packet;
    int64_t queued_ns = 0;
  };
  void grow();  // under mutex_
  // Under mutex_: moves the front entry out; returns its queue time and whether the queue
  // was at capacity before.
  void pop_locked(Packet& out, int64_t& queued_ns, bool& was_full);
  void account_take(int64_t now_ns, int64_t queued_ns, bool was_full);

  const std::string name_;
  const StreamOptions options_;
  const Clock& clock_;
  Wakeable* producer_ = nullptr;
  Wakeable* consumer_ = nullptr;

  mutable std::mutex mutex_;
  std::vector<Entry> ring_;  // power-of-two size, grows only when a lossless queue overshoots
  std::size_t head_ = 0;
  std::size_t count_ = 0;
  Timestamp bound_ = kTimestampMin;
  bool flag_next_push_ = false;     // drop_newest: the gap is before the next accepted packet
  uint32_t consecutive_drops_ = 0;  // since the consumer last took a packet
  std::atomic<std::size_t> size_{0};

  Counter pushed_, delivered_, dropped_, high_water_;
  LatencyHistogram latency_;
  WatchPoint watch_;
};

}  // namespace marvin::graph
