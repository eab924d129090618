// The built-in nodes that are not framework pieces of their own: sources and sinks for demos,
// tests and benchmarks, and the two bridges between a graph and its host.
//
//   SyntheticAudioSource  -> out (AudioChunk)
//       sample_rate (16000), chunk_samples (320), duration_ms (2000; 0 = until stopped),
//       pace (1.0 = real time, 2.0 = twice as fast, 0 = as fast as possible),
//       waveform ("sine" | "ramp": sample i is i mod 32768, handy in tests),
//       frequency_hz (440), amplitude (8000)
//   ToggleSource          -> out (bool), an AttentionNode
//       period_ms (500): the state flips every period; tick_ms (50): how often the bound
//       advances; duration_ms (2000); pace (1.0); start_open (true)
//   CounterSource         -> out (int64): 0, 1, 2, ... stamped 0, 1, 2, ...
//       count (0 = until stopped), interval_us (0 = as fast as the streams take them;
//       otherwise packet n is due n * interval_us after the first, in real time)
//   PassThrough           in (any) -> out (same type): forwards every packet
//   Sink                  in (any): takes every packet (counters show how many)
//   GraphInput            -> out (option "type", default "any"): packets given to Graph::push();
//                            finishes after Graph::close_input()
//   WatchdogEvents        -> events (WatchdogEvent): the graph's watchdog events; finishes
//                            when every other source has
#pragma once

#include <deque>
#include <mutex>

#include "graph/attention_node.h"
#include "graph/node.h"
#include "graph/watchdog.h"

namespace marvin::graph {

class GraphInputNode : public Node {
 public:
  static void declare(Contract& c);
  void process(Context& ctx) override;
  // Thread-safe; called by Graph::push / Graph::close_input.
  void enqueue(Packet packet);
  void close_input();

 private:
  std::mutex mutex_;
  std::deque<Packet> queue_;
  bool closed_ = false;
};

class WatchdogEventsNode : public Node {
 public:
  static void declare(Contract& c);
  void process(Context& ctx) override;
  // Thread-safe; called from the watchdog's thread.
  void enqueue(const WatchdogEvent& event);

 private:
  std::mutex mutex_;
  std::deque<WatchdogEvent> queue_;
  Timestamp last_ = kTimestampMin;
};

}  // namespace marvin::graph
