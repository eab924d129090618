#include "graph/node_runtime.h"

#include <chrono>

#include "graph/graph_config.h"

namespace marvin::graph {

// ---- Context ----

const std::string& Context::node_name() const { return rt_->name(); }
const Options& Context::options() const { return rt_->options(); }
void Context::emit(int port, Packet packet) { rt_->emit(port, std::move(packet)); }
void Context::set_bound(int port, Timestamp next) { rt_->set_bound(port, next); }
bool Context::stop_requested() const { return rt_->stop_requested(); }
int64_t Context::now_ns() const { return rt_->clock().now_ns(); }

void Context::wake_after(std::chrono::nanoseconds delay) {
  const auto now = std::chrono::steady_clock::now().time_since_epoch();
  wake_at_ns_ = std::chrono::duration_cast<std::chrono::nanoseconds>(now + delay).count();
  if (wake_at_ns_ == 0) wake_at_ns_ = 1;
}

namespace detail {
namespace {

// Process calls per turn on a worker before the node goes to the back of the run queue:
// large enough to amortise scheduling, small enough to keep per-hop latency low.
constexpr int kBatch = 64;

int64_t steady_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

}  // namespace

NodeRuntime::NodeRuntime(int index, std::string name, std::string type, std::unique_ptr<Node> node,
                         Options options, InputPolicy policy, bool daemon, GraphShared& shared)
    : index_(index),
      name_(std::move(name)),
      type_(std::move(type)),
      node_(std::move(node)),
      options_(std::move(options)),
      policy_(policy),
      daemon_(daemon),
      shared_(shared),
      ctx_(this) {}

bool NodeRuntime::stop_requested() const {
  if (shared_.stop_requested.load(std::memory_order_acquire)) return true;
  return daemon_ && shared_.live_sources.load(std::memory_order_acquire) == 0;
}

void NodeRuntime::wake() {
  int s = state_.load(std::memory_order_acquire);
  for (;;) {
    if (s == kRerun) return;
    if (s == kQueued) {
      if (state_.compare_exchange_weak(s, kRerun, std::memory_order_acq_rel)) return;
      continue;
    }
    if (state_.compare_exchange_weak(s, kQueued, std::memory_order_acq_rel)) {
      shared_.scheduler->submit(this);
      return;
    }
  }
}

void NodeRuntime::run() {
  // From here on, a wake() asks for another turn; this turn sees everything before it.
  state_.store(kQueued, std::memory_order_seq_cst);
  bool more = false;
  if (!done_ && opened_ && !shared_.cancelled.load(std::memory_order_acquire)) more = run_batch();
  if (!more) {
    int expected = kQueued;
    if (state_.compare_exchange_strong(expected, kIdle, std::memory_order_acq_rel)) return;
    state_.store(kQueued, std::memory_order_release);
  }
  shared_.scheduler->submit(this);
}

void NodeRuntime::open() {
  for (const OutputPort& o : outputs) {
    for (Stream* s : o.streams) {
      if (s->options().policy == StreamPolicy::kLossless && !s->options().back_edge) {
        lossless_out_.push_back(s);
      }
    }
  }
  heads_.resize(inputs.size());
  ctx_.inputs_.assign(inputs.size(), Packet());
  ctx_.input_ts_ = kTimestampUnset;
  try {
    node_->open(ctx_);
  } catch (const std::exception& e) {
    throw GraphError(describe() + " failed in open(): " + e.what());
  }
  opened_ = true;
}

void NodeRuntime::close_if_open() {
  if (!opened_ || closed_) return;
  closed_ = true;
  ctx_.input_ts_ = kTimestampUnset;
  try {
    node_->close(ctx_);
  } catch (const std::exception&) {
    // The graph already failed or was cancelled; the first error is the one reported.
  }
}

bool NodeRuntime::outputs_full() const {
  for (const Stream* s : lossless_out_) {
    if (s->full()) return true;
  }
  return false;
}

bool NodeRuntime::run_batch() {
  now_ns_ = shared_.clock->now_ns();
  for (int i = 0; i < kBatch; ++i) {
    if (done_ || shared_.cancelled.load(std::memory_order_relaxed)) return false;
    if (outputs_full()) return false;  // the consumer wakes us when it takes a packet
    if (!(is_source() ? source_step() : input_step())) return false;
  }
  return true;
}

bool NodeRuntime::call(const char* what, void (Node::*method)(Context&)) {
  const int64_t start = now_ns_;
  try {
    (node_.get()->*method)(ctx_);
  } catch (const std::exception& e) {
    std::string at = ctx_.input_ts_ == kTimestampUnset
                         ? std::string()
                         : " at timestamp " + std::to_string(ctx_.input_ts_);
    shared_.fail(describe() + " failed in " + what + "()" + at + ": " + e.what());
    return false;
  }
  const int64_t end = shared_.clock->now_ns();
  now_ns_ = end;
  if (method != &Node::process) return true;
  calls_.add();
  process_time_.record(end - start);
  watch_.record_activity(start);
  watch_.record_latency(end - start);
  if (shared_.trace) shared_.trace->record(Scheduler::worker_index(), index_, start, end - start);
  return true;
}

bool NodeRuntime::source_step() {
  if (stop_requested()) {
    finish();
    return false;
  }
  if (wake_at_ns_ != 0) {
    if (steady_ns() < wake_at_ns_) return false;  // woken early; the timer will come
    wake_at_ns_ = 0;
  }
  ctx_.input_ts_ = kTimestampUnset;
  ctx_.sleep_ = false;
  ctx_.wake_at_ns_ = 0;
  if (!call("process", &Node::process)) return false;
  if (ctx_.finished_) {
    finish();
    return false;
  }
  if (ctx_.wake_at_ns_ != 0) {
    wake_at_ns_ = ctx_.wake_at_ns_;
    shared_.scheduler->wake_at(this, wake_at_ns_);
    return false;
  }
  return !ctx_.sleep_;
}

bool NodeRuntime::input_step() {
  const std::size_t n = inputs.size();
  // Back-edge packets bypass synchronisation: each is processed on its own as it comes.
  for (std::size_t i = 0; i < n; ++i) {
    InputSlot& in = inputs[i];
    if (!in.back_edge || !in.stream) continue;
    if (in.stream->head().has_packet) {
      for (Packet& p : ctx_.inputs_) p = Packet();
      ctx_.inputs_[i] = in.stream->take(now_ns_);
      ctx_.input_ts_ = ctx_.inputs_[i].timestamp();
      return call("process", &Node::process);
    }
  }

  if (n == 1 && !inputs[0].back_edge) return single_input_step();

  Timestamp min_next = kTimestampDone;
  for (std::size_t i = 0; i < n; ++i) {
    const InputSlot& in = inputs[i];
    if (in.back_edge) continue;
    if (in.stream) {
      heads_[i] = in.stream->head();
    } else {
      heads_[i] = Stream::Head{false, kTimestampDone, kTimestampDone};
    }
    if (heads_[i].next_possible() < min_next) min_next = heads_[i].next_possible();
  }
  if (min_next == kTimestampDone) {
    finish();
    return false;
  }

  Timestamp ts = min_next;
  if (policy_ == InputPolicy::kSynchronized) {
    for (std::size_t i = 0; i < n; ++i) {
      if (inputs[i].back_edge) continue;
      const Stream::Head& h = heads_[i];
      // Ready only when every input either has its packet at `ts` or cannot get one any more.
      if (!(h.has_packet && h.front == ts) && h.next_possible() <= ts) {
        propagate_bound(min_next);
        return false;
      }
    }
    for (std::size_t i = 0; i < n; ++i) {
      const Stream::Head& h = heads_[i];
      const bool here = !inputs[i].back_edge && h.has_packet && h.front == ts;
      ctx_.inputs_[i] = here ? inputs[i].stream->take(now_ns_) : Packet();
    }
  } else {
    std::size_t pick = n;
    for (std::size_t i = 0; i < n; ++i) {
      if (inputs[i].back_edge || !heads_[i].has_packet) continue;
      if (pick == n || heads_[i].front < heads_[pick].front) pick = i;
    }
    if (pick == n) {
      propagate_bound(min_next);
      return false;
    }
    for (Packet& p : ctx_.inputs_) p = Packet();
    ctx_.inputs_[pick] = inputs[pick].stream->take(now_ns_);
    ts = heads_[pick].front;
  }
  ctx_.input_ts_ = ts;
  if (!call("process", &Node::process)) return false;
  for (Packet& p : ctx_.inputs_) p = Packet();
  // Nothing below what the inputs may still bring can come out of this node any more.
  propagate_bound(policy_ == InputPolicy::kSynchronized ? ts + 1 : min_next);
  return true;
}

// The common case of one input: both policies agree, and one lock takes the packet.
bool NodeRuntime::single_input_step() {
  Stream* stream = inputs[0].stream;
  if (!stream) {
    finish();
    return false;
  }
  const Stream::Head h = stream->poll(ctx_.inputs_[0], now_ns_);
  if (!h.has_packet) {
    if (h.bound == kTimestampDone) {
      finish();
    } else {
      propagate_bound(h.bound);
    }
    return false;
  }
  ctx_.input_ts_ = h.front;
  if (!call("process", &Node::process)) return false;
  ctx_.inputs_[0] = Packet();
  propagate_bound(h.front + 1);
  return true;
}

void NodeRuntime::propagate_bound(Timestamp next) {
  for (OutputPort& o : outputs) {
    if (next <= o.bound) continue;
    o.bound = next;
    for (Stream* s : o.streams) s->advance_bound(next);
  }
}

void NodeRuntime::emit(int port, Packet packet) {
  if (port < 0 || static_cast<std::size_t>(port) >= outputs.size()) {
    throw std::out_of_range(describe() + " has no output port #" + std::to_string(port));
  }
  OutputPort& o = outputs[static_cast<std::size_t>(port)];
  const Timestamp ts = packet.timestamp();
  if (packet.empty()) throw std::logic_error(describe() + " output '" + o.name + "': empty packet");
  if (ts == kTimestampUnset) {
    throw std::logic_error(describe() + " output '" + o.name + "': packet has no timestamp");
  }
  if (ts < o.bound) {
    throw std::logic_error(describe() + " output '" + o.name + "': timestamp " +
                           std::to_string(ts) + " is below the port's bound " +
                           std::to_string(o.bound) + " (timestamps must increase)");
  }
  if (packet.type_name() != o.checked_type) {
    if (o.type != "any" && !same_type(o.type.c_str(), packet.type_name())) {
      throw std::logic_error(describe() + " output '" + o.name + "' is declared '" + o.type +
                             "' but the packet holds '" + packet.type_name() + "'");
    }
    o.checked_type = packet.type_name();
  }
  o.bound = ts + 1;
  emitted_.add();
  for (const PacketObserver& observe : o.observers) observe(packet);
  const std::size_t n = o.streams.size();
  for (std::size_t i = 0; i + 1 < n; ++i) o.streams[i]->push(packet, now_ns_);
  if (n > 0) o.streams[n - 1]->push(std::move(packet), now_ns_);
}

void NodeRuntime::set_bound(int port, Timestamp next) {
  if (port < 0 || static_cast<std::size_t>(port) >= outputs.size()) {
    throw std::out_of_range(describe() + " has no output port #" + std::to_string(port));
  }
  OutputPort& o = outputs[static_cast<std::size_t>(port)];
  if (next <= o.bound) return;
  o.bound = next;
  for (Stream* s : o.streams) s->advance_bound(next);
}

void NodeRuntime::finish() {
  if (done_) return;
  if (opened_ && !closed_) {
    closed_ = true;
    ctx_.input_ts_ = kTimestampUnset;
    if (!call("close", &Node::close)) {
      done_ = true;
      return;  // the graph is failing; it closes what is left
    }
  }
  done_ = true;
  watch_.finished.store(true, std::memory_order_release);
  for (OutputPort& o : outputs) {
    o.bound = kTimestampDone;
    for (Stream* s : o.streams) {
      s->watch_point().finished.store(true, std::memory_order_release);
      s->close();
    }
  }
  shared_.node_finished(is_source(), daemon_);
}

NodeStats NodeRuntime::stats() const {
  NodeStats s;
  s.name = name_;
  s.type = type_;
  s.process_calls = calls_.get();
  s.emitted = emitted_.get();
  s.process_p50_ns = process_time_.quantile(0.50);
  s.process_p99_ns = process_time_.quantile(0.99);
  return s;
}

}  // namespace detail
}  // namespace marvin::graph
