// Graph: a validated set of nodes and streams, run on a bounded pool of threads.
//
//   GraphConfig config = load_graph_config("examples/graphs/audio_demo.json");
//   Graph graph(config);            // validates; throws GraphError naming node/port/types
//   graph.start();                  // opens every node, starts the workers and the watchdog
//   if (!graph.wait_for(2s)) graph.stop();
//   graph.wait();                   // throws GraphError if a node failed
//   std::cout << graph.stats().to_text();
//
// VALIDATION (in the constructor, before anything runs): unknown node type, duplicate node,
// bad or unknown option, unknown port, input fed twice, required input not connected, type
// mismatch between the two ends of a stream, and cycles that do not go through a stream
// declared "back_edge". Every error names the node(s), port(s) and both types; all the
// errors found are reported together, one per line.
//
// RUNNING: nodes run on `threads` workers (see node.h for the guarantees a node gets).
// The graph finishes on its own when every source has finished and every stream drained.
// stop() asks the sources to finish now; streams still drain, so lossless streams lose
// nothing. cancel() stops at once, dropping what is queued. A node that throws stops the
// graph: wait() then throws its error. Nothing here blocks forever on a failure.
//
// Thread-safety: start/stop/cancel/wait/stats/push may be called from any one thread;
// stats() and push() also concurrently with a running graph. The destructor cancels a
// running graph and joins its threads.
#pragma once

#include <chrono>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <string>
#include <string_view>
#include <vector>

#include "graph/clock.h"
#include "graph/graph_config.h"
#include "graph/node.h"
#include "graph/node_runtime.h"
#include "graph/scheduler.h"
#include "graph/stats.h"
#include "graph/stream.h"
#include "graph/trace.h"
#include "graph/watchdog.h"

namespace marvin::graph {

struct GraphOptions {
  // Worker threads; 0 takes the config's "threads".
  int threads = 0;
  // Time for latencies, rates and the watchdog; null means SteadyClock. Must outlive the graph.
  const Clock* clock = nullptr;
  // Record a span per process() call for write_trace().
  bool trace = false;
  // Run the watchdog on its own thread; tests set false and call watchdog().check().
  bool watchdog_thread = true;
  // Where node types are looked up; null means NodeRegistry::global().
  const NodeRegistry* registry = nullptr;
};

class Graph {
 public:
  // Builds and validates the graph. Throws GraphError listing every problem found.
  explicit Graph(GraphConfig config, GraphOptions options = {});
  ~Graph();
  Graph(const Graph&) = delete;
  Graph& operator=(const Graph&) = delete;

  // Calls `observer` with every packet emitted on `output` ("node.port"), on the emitting
  // node's thread, before the packet is queued. Call before start(). Throws GraphError for
  // an unknown port.
  void observe(std::string_view output, PacketObserver observer);

  // Opens every node (in config order, on this thread) and starts running. If an open()
  // throws, the nodes already opened are closed and GraphError is thrown. Call once.
  void start();

  // Feeds a "GraphInput" node named `input` (the packet needs a timestamp). Never blocks:
  // a GraphInput queues without bound. Throws GraphError if there is no such input node.
  void push(std::string_view input, Packet packet);
  // Tells a GraphInput no more packets will come.
  void close_input(std::string_view input);

  // Asks every source to finish; the graph then drains and finishes. Returns at once.
  void stop();
  // Stops at once: no more process() calls; queued packets are dropped. Returns at once.
  void cancel();

  // Blocks until the graph finished (or was cancelled), joins its threads and closes any node
  // still open. Throws GraphError with the first node failure. Idempotent.
  void wait();
  // Like wait() but gives up after `timeout`; returns true when the graph finished (then
  // also joins and may throw like wait()).
  bool wait_for(std::chrono::nanoseconds timeout);

  // Counters, readable while the graph runs.
  GraphStats stats() const;
  // Graphviz description: one box per node, one edge per stream with its type and policy.
  std::string to_dot() const;
  // Writes the Chrome trace (GraphOptions::trace must be on). Call after wait().
  void write_trace(const std::string& path) const;

  Watchdog& watchdog() { return *watchdog_; }
  int threads() const { return scheduler_->threads(); }

 private:
  void build(const NodeRegistry& registry);
  void fail(const std::string& error);
  void node_finished(bool source, bool daemon);
  void join();
  detail::NodeRuntime* find_node(std::string_view name) const;
  void on_watchdog_event(const WatchdogEvent& event);

  GraphConfig config_;
  GraphOptions options_;
  const Clock* clock_;
  detail::GraphShared shared_;
  std::unique_ptr<Scheduler> scheduler_;
  std::unique_ptr<Watchdog> watchdog_;
  std::unique_ptr<TraceRecorder> trace_;
  std::vector<std::unique_ptr<Stream>> streams_;
  std::vector<std::unique_ptr<detail::NodeRuntime>> nodes_;
  std::vector<detail::NodeRuntime*> event_nodes_;  // WatchdogEvents nodes

  mutable std::mutex mutex_;
  std::condition_variable finished_cv_;
  int remaining_ = 0;
  bool started_ = false, finished_ = false, joined_ = false;
  std::string error_;
};

}  // namespace marvin::graph
