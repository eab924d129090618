// Internal: how the graph runs one node (scheduling state, ports, counters). Not part of the
// public API; node authors see only Context (node.h).
#pragma once

#include <atomic>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "graph/clock.h"
#include "graph/node.h"
#include "graph/scheduler.h"
#include "graph/stats.h"
#include "graph/stream.h"
#include "graph/trace.h"
#include "graph/watchdog.h"

namespace marvin::graph {

using PacketObserver = std::function<void(const Packet&)>;

namespace detail {

// What every node of one graph shares with the graph.
struct GraphShared {
  const Clock* clock = nullptr;
  Scheduler* scheduler = nullptr;
  TraceRecorder* trace = nullptr;
  std::atomic<bool> stop_requested{false};
  std::atomic<bool> cancelled{false};
  std::atomic<int> live_sources{0};  // non-daemon sources not finished yet
  std::function<void(const std::string& error)> fail;  // first error wins; cancels the graph
  std::function<void(bool source, bool daemon)> node_finished;
};

struct OutputPort {
  std::string name;
  std::string type;  // resolved; "any" when unknown
  std::vector<Stream*> streams;
  std::vector<PacketObserver> observers;
  Timestamp bound = kTimestampMin;
  const char* checked_type = nullptr;  // last payload type name found to match `type`
};

struct InputSlot {
  std::string name;
  std::string type;
  Stream* stream = nullptr;  // null: not connected (treated as a finished stream)
  bool back_edge = false;
};

class NodeRuntime final : public Task, public Wakeable {
 public:
  NodeRuntime(int index, std::string name, std::string type, std::unique_ptr<Node> node,
              Options options, InputPolicy policy, bool daemon, GraphShared& shared);

  // Task / Wakeable: may be called from any thread.
  void wake() override;
  void run() override;

  // Graph::start(), on the starting thread. Throws GraphError naming the node.
  void open();
  // After the workers stopped (error or cancel): close() if open() ran and close() did not.
  void close_if_open();

  void emit(int port, Packet packet);
  void set_bound(int port, Timestamp next);

  NodeStats stats() const;
  const std::string& name() const { return name_; }
  const std::string& type() const { return type_; }
  const Options& options() const { return options_; }
  Node* node() const { return node_.get(); }
  bool is_source() const { return inputs.empty(); }
  bool daemon() const { return daemon_; }
  bool stop_requested() const;
  const Clock& clock() const { return *shared_.clock; }
  WatchPoint& watch_point() { return watch_; }

  std::vector<InputSlot> inputs;
  std::vector<OutputPort> outputs;

 private:
  bool run_batch();
  bool source_step();
  bool input_step();
  bool single_input_step();
  bool outputs_full() const;
  bool call(const char* what, void (Node::*method)(Context&));
  void propagate_bound(Timestamp next);
  void finish();
  std::string describe() const { return "node '" + name_ + "' (" + type_ + ")"; }

  enum : int { kIdle = 0, kQueued = 1, kRerun = 2 };
  std::atomic<int> state_{kIdle};

  const int index_;
  const std::string name_, type_;
  std::unique_ptr<Node> node_;
  const Options options_;
  const InputPolicy policy_;
  const bool daemon_;
  GraphShared& shared_;
  Context ctx_;

  // Touched only by the thread running the node.
  bool opened_ = false, closed_ = false, done_ = false;
  int64_t wake_at_ns_ = 0;
  // Latest clock reading: refreshed once per process() call and reused for queue timestamps,
  // because reading the clock costs more than the rest of a hop.
  int64_t now_ns_ = 0;
  std::vector<Stream::Head> heads_;
  std::vector<Stream*> lossless_out_;

  Counter calls_, emitted_;
  LatencyHistogram process_time_;
  WatchPoint watch_;
};

}  // namespace detail
}  // namespace marvin::graph
