// Node: one step of a perception graph (a microphone source, a feature extractor, a latch).
//
// LIFE CYCLE AND THREADING (the rules every node can rely on)
//
//   1. declare(Contract&)  static, called when the graph is built (Graph's constructor),
//                          possibly several times, with the node's options. Declares typed
//                          ports, options and the default input policy (see contract.h).
//                          Nothing runs yet; a miswired graph fails here, naming node, port
//                          and types.
//   2. construction        by the registry's factory, when the graph is built.
//   3. open(ctx)           once, in Graph::start(), on the thread calling start(), before any
//                          process(). Read options here. May emit nothing. Throwing makes
//                          start() fail with the node's name; close() is then not called.
//   4. process(ctx)        repeatedly, on the graph's worker threads, but NEVER on two threads
//                          at once for the same node, and with happens-before between
//                          successive calls: a node needs no locking for its own members.
//                            - a node with inputs is called when its input policy finds a
//                              timestamp ready (ctx.input_timestamp(); see InputPolicy);
//                            - a source (no inputs) is called again and again while its
//                              outputs have room, until it calls ctx.finish(); it may pace
//                              itself with ctx.wake_after() or ctx.sleep_until_woken().
//   5. close(ctx)          once, after the last process(): when every input is done (or the
//                          source finished), or when the graph stops on an error or cancel.
//                          Outputs are closed (bound = done) right after it returns.
//
// FAILURE: an exception from open/process/close stops the whole graph; Graph::wait() throws
// a GraphError naming the node, its type, the call and the timestamp. Other nodes see no
// more process() calls and get close().
//
// TIMESTAMPS: packets emitted on one output must have strictly increasing timestamps, and a
// node must not emit below the input timestamp it is processing. The framework relies on this
// to advance each output's bound after every call (and whenever the inputs' bounds advance),
// so a node that emits nothing for an input (a closed latch, no detection) still lets nodes
// downstream move on. A source that emits nothing for a while should ctx.set_bound().
//
// REGISTRATION: a node class is registered by name, so graphs can be described in JSON:
//
//   class Doubler : public marvin::graph::Node {
//    public:
//     static void declare(Contract& c) { c.add_input<int64_t>("in"); c.add_output<int64_t>("out"); }
//     void process(Context& ctx) override { ctx.emit(0, 2 * ctx.input(0).get<int64_t>()); }
//   };
//   MARVIN_REGISTER_NODE(Doubler, "Doubler");
#pragma once

#include <chrono>
#include <concepts>
#include <cstdint>
#include <memory>
#include <string>
#include <type_traits>
#include <vector>

#include "graph/contract.h"
#include "graph/packet.h"

namespace marvin::graph {

namespace detail {
class NodeRuntime;
}

// What a node sees during open/process/close. Only valid during the call it is passed to.
class Context {
 public:
  const std::string& node_name() const;
  const Options& options() const;

  // ---- inputs (process only) ----
  // Timestamp being processed (kTimestampUnset for sources and in open/close).
  Timestamp input_timestamp() const { return input_ts_; }
  int input_count() const { return static_cast<int>(inputs_.size()); }
  // The packet on input `port` at input_timestamp(), or an empty packet.
  const Packet& input(int port) const { return inputs_[static_cast<std::size_t>(port)]; }
  bool has_input(int port) const { return !input(port).empty(); }
  // Moves the packet out, e.g. to consume() its payload when this node is the only owner.
  Packet take_input(int port) { return std::move(inputs_[static_cast<std::size_t>(port)]); }

  // ---- outputs ----
  // Sends `packet` on output `port` to every connected stream. Its timestamp must be set and
  // above the port's previous one; throws std::logic_error naming node and port otherwise.
  void emit(int port, Packet packet);
  // Wraps `value` in a packet stamped with input_timestamp() and emits it.
  template <typename T>
    requires(!std::same_as<std::decay_t<T>, Packet>)
  void emit(int port, T&& value) {
    emit(port, Packet::make<std::decay_t<T>>(std::forward<T>(value)).at(input_ts_));
  }
  // Promises no packet below `next` on output `port` (raises the bound; never lowers it).
  void set_bound(int port, Timestamp next);

  // ---- sources ----
  // No more output: the node is closed after this call.
  void finish() { finished_ = true; }
  // Do not call process() again before `delay` has passed (real time).
  void wake_after(std::chrono::nanoseconds delay);
  // Do not call process() again until something outside wakes the node (graph inputs).
  void sleep_until_woken() { sleep_ = true; }
  // True once Graph::stop() was called: a source should finish.
  bool stop_requested() const;

  // The graph's clock (nanoseconds; see clock.h).
  int64_t now_ns() const;

 private:
  friend class detail::NodeRuntime;
  explicit Context(detail::NodeRuntime* runtime) : rt_(runtime) {}

  detail::NodeRuntime* rt_;
  std::vector<Packet> inputs_;
  Timestamp input_ts_ = kTimestampUnset;
  bool finished_ = false;
  bool sleep_ = false;
  int64_t wake_at_ns_ = 0;  // steady clock; 0 = none
};

// Base of every node. Subclasses also provide `static void declare(Contract&)`.
class Node {
 public:
  virtual ~Node() = default;
  virtual void open(Context& ctx) { (void)ctx; }
  virtual void process(Context& ctx) = 0;
  virtual void close(Context& ctx) { (void)ctx; }
};

}  // namespace marvin::graph

#include "graph/node_registry.h"
