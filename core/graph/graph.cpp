#include "graph/graph.h"

#include <algorithm>
#include <fstream>
#include <functional>
#include <map>

#include "common/log.h"
#include "graph/builtin_nodes.h"

namespace marvin::graph {
namespace {

struct Endpoint {
  std::string node, port;
};

bool split_endpoint(const std::string& text, Endpoint& out) {
  const auto dot = text.find('.');
  if (dot == std::string::npos || dot == 0 || dot + 1 == text.size()) return false;
  out.node = text.substr(0, dot);
  out.port = text.substr(dot + 1);
  return true;
}

std::string port_list(const std::vector<PortSpec>& ports) {
  if (ports.empty()) return "none";
  std::string s;
  for (const PortSpec& p : ports) s += (s.empty() ? "" : ", ") + p.name + " (" + p.type + ")";
  return s;
}

int find_port(const std::vector<PortSpec>& ports, const std::string& name) {
  for (std::size_t i = 0; i < ports.size(); ++i) {
    if (ports[i].name == name) return static_cast<int>(i);
  }
  return -1;
}

constexpr std::string_view kSameAs = "same_as:";

// Everything the validation learns about one node.
struct Declared {
  const NodeType* type = nullptr;
  std::unique_ptr<Contract> contract;
  std::vector<int> input_stream;  // per input: index of the stream feeding it, -1 if none
  std::vector<std::string> out_type;  // resolved output types
};

struct Wire {
  int from_node, from_port, to_node, to_port;
};

[[noreturn]] void throw_all(const std::vector<std::string>& errors) {
  std::string text;
  for (const std::string& e : errors) text += (text.empty() ? "" : "\n") + e;
  throw GraphError(text);
}

}  // namespace

Graph::Graph(GraphConfig config, GraphOptions options)
    : config_(std::move(config)),
      options_(options),
      clock_(options.clock ? options.clock : &SteadyClock::instance()) {
  build(options_.registry ? *options_.registry : NodeRegistry::global());
}

Graph::~Graph() {
  if (started_) {
    cancel();
    try {
      wait();
    } catch (const std::exception&) {
      // A destructor cannot report; whoever cared called wait() before.
    }
  }
}

void Graph::build(const NodeRegistry& registry) {
  std::vector<std::string> errors;
  const std::size_t n = config_.nodes.size();
  std::vector<Declared> decl(n);
  std::map<std::string, int, std::less<>> by_name;

  // 1. Node types, names and contracts (with options).
  for (std::size_t i = 0; i < n; ++i) {
    const NodeConfig& nc = config_.nodes[i];
    if (nc.name.empty() || nc.name.find('.') != std::string::npos) {
      errors.push_back("node #" + std::to_string(i) + ": name '" + nc.name +
                       "' must be non-empty and contain no '.'");
      continue;
    }
    if (!by_name.emplace(nc.name, static_cast<int>(i)).second) {
      errors.push_back("node '" + nc.name + "': the name is used by two nodes");
      continue;
    }
    decl[i].type = registry.find(nc.type);
    if (!decl[i].type) {
      std::string known;
      for (const std::string& t : registry.names()) known += (known.empty() ? "" : ", ") + t;
      errors.push_back("node '" + nc.name + "': unknown node type '" + nc.type + "' (known: " +
                       known + ")");
      continue;
    }
    try {
      decl[i].contract = std::make_unique<Contract>(nc.options);
      decl[i].type->declare(*decl[i].contract);
      decl[i].contract->check_no_unknown_options();
    } catch (const std::exception& e) {
      errors.push_back("node '" + nc.name + "' (" + nc.type + "): " + e.what());
      decl[i].contract.reset();
      continue;
    }
    decl[i].input_stream.assign(decl[i].contract->inputs().size(), -1);
  }
  if (!errors.empty()) throw_all(errors);

  // 2. Streams: endpoints exist, each input fed once.
  std::vector<Wire> wires(config_.streams.size());
  for (std::size_t s = 0; s < config_.streams.size(); ++s) {
    const StreamConfig& sc = config_.streams[s];
    const std::string what = "stream '" + sc.from + " -> " + sc.to + "'";
    Endpoint from, to;
    if (!split_endpoint(sc.from, from) || !split_endpoint(sc.to, to)) {
      errors.push_back(what + ": endpoints must be written \"node.port\"");
      continue;
    }
    auto f = by_name.find(from.node);
    auto t = by_name.find(to.node);
    if (f == by_name.end() || t == by_name.end()) {
      errors.push_back(what + ": no node named '" + (f == by_name.end() ? from.node : to.node) + "'");
      continue;
    }
    Declared& fd = decl[static_cast<std::size_t>(f->second)];
    Declared& td = decl[static_cast<std::size_t>(t->second)];
    const int op = find_port(fd.contract->outputs(), from.port);
    const int ip = find_port(td.contract->inputs(), to.port);
    if (op < 0) {
      errors.push_back(what + ": node '" + from.node + "' (" + fd.type->name +
                       ") has no output port '" + from.port + "' (outputs: " +
                       port_list(fd.contract->outputs()) + ")");
      continue;
    }
    if (ip < 0) {
      errors.push_back(what + ": node '" + to.node + "' (" + td.type->name +
                       ") has no input port '" + to.port + "' (inputs: " +
                       port_list(td.contract->inputs()) + ")");
      continue;
    }
    int& feeder = td.input_stream[static_cast<std::size_t>(ip)];
    if (feeder >= 0) {
      errors.push_back(what + ": input '" + sc.to + "' is already fed by stream '" +
                       config_.streams[static_cast<std::size_t>(feeder)].from + " -> " + sc.to +
                       "' (an input takes one stream; fan-out is from outputs)");
      continue;
    }
    feeder = static_cast<int>(s);
    wires[s] = {f->second, op, t->second, ip};
  }
  for (std::size_t i = 0; i < n; ++i) {
    const auto& inputs = decl[i].contract->inputs();
    for (std::size_t p = 0; p < inputs.size(); ++p) {
      if (!inputs[p].optional && decl[i].input_stream[p] < 0) {
        errors.push_back("node '" + config_.nodes[i].name + "' (" + decl[i].type->name +
                         "): required input '" + inputs[p].name + "' (" + inputs[p].type +
                         ") is not connected");
      }
    }
  }
  if (!errors.empty()) throw_all(errors);

  // 3. Resolve "same_as:<input>" output types, then check both ends of every stream.
  for (Declared& d : decl) {
    for (const PortSpec& o : d.contract->outputs()) d.out_type.push_back(o.type);
  }
  for (std::size_t pass = 0; pass <= n; ++pass) {
    bool changed = false;
    for (Declared& d : decl) {
      for (std::string& type : d.out_type) {
        if (type.rfind(kSameAs, 0) != 0) continue;
        const int ip = find_port(d.contract->inputs(), type.substr(kSameAs.size()));
        if (ip < 0 || d.input_stream[static_cast<std::size_t>(ip)] < 0) {
          type = "any";
          changed = true;
          continue;
        }
        const Wire& w = wires[static_cast<std::size_t>(d.input_stream[static_cast<std::size_t>(ip)])];
        const std::string& up = decl[static_cast<std::size_t>(w.from_node)]
                                    .out_type[static_cast<std::size_t>(w.from_port)];
        if (up.rfind(kSameAs, 0) != 0) {
          type = up;
          changed = true;
        }
      }
    }
    if (!changed) break;
  }
  for (Declared& d : decl) {
    for (std::string& type : d.out_type) {
      if (type.rfind(kSameAs, 0) == 0) type = "any";  // a loop of pass-through nodes
    }
  }
  for (std::size_t s = 0; s < wires.size(); ++s) {
    const Wire& w = wires[s];
    const Declared& fd = decl[static_cast<std::size_t>(w.from_node)];
    const Declared& td = decl[static_cast<std::size_t>(w.to_node)];
    const std::string& out = fd.out_type[static_cast<std::size_t>(w.from_port)];
    const std::string& in = td.contract->inputs()[static_cast<std::size_t>(w.to_port)].type;
    if (out != "any" && in != "any" && out != in) {
      const StreamConfig& sc = config_.streams[s];
      errors.push_back("stream '" + sc.from + " -> " + sc.to + "': type mismatch: output '" +
                       sc.from + "' of node '" + config_.nodes[static_cast<std::size_t>(w.from_node)].name +
                       "' (" + fd.type->name + ") carries '" + out + "' but input '" + sc.to +
                       "' of node '" + config_.nodes[static_cast<std::size_t>(w.to_node)].name +
                       "' (" + td.type->name + ") expects '" + in + "'");
    }
  }
  if (!errors.empty()) throw_all(errors);

  // 4. Cycles must pass through a declared back edge.
  {
    std::vector<std::vector<std::size_t>> out_streams(n);
    for (std::size_t s = 0; s < wires.size(); ++s) {
      if (!config_.streams[s].options.back_edge) {
        out_streams[static_cast<std::size_t>(wires[s].from_node)].push_back(s);
      }
    }
    std::vector<int> color(n, 0);  // 0 new, 1 on the path, 2 done
    std::vector<std::size_t> path;  // streams
    std::string cycle;
    std::function<bool(std::size_t)> visit = [&](std::size_t v) {
      color[v] = 1;
      for (std::size_t s : out_streams[v]) {
        const auto next = static_cast<std::size_t>(wires[s].to_node);
        path.push_back(s);
        if (color[next] == 1) {
          std::size_t start = path.size() - 1;
          while (start > 0 && static_cast<std::size_t>(wires[path[start]].from_node) != next) --start;
          for (std::size_t k = start; k < path.size(); ++k) {
            cycle += (cycle.empty() ? "" : ", ") + config_.streams[path[k]].from + " -> " +
                     config_.streams[path[k]].to;
          }
          return true;
        }
        if (color[next] == 0 && visit(next)) return true;
        path.pop_back();
      }
      color[v] = 2;
      return false;
    };
    for (std::size_t v = 0; v < n && cycle.empty(); ++v) {
      if (color[v] == 0) visit(v);
    }
    if (!cycle.empty()) {
      throw GraphError("cycle without a back edge: " + cycle +
                       " (mark one of these streams \"back_edge\": true)");
    }
  }

  // 5. Everything is valid: create nodes and streams.
  const int threads = options_.threads > 0 ? options_.threads : config_.threads;
  scheduler_ = std::make_unique<Scheduler>(threads, n + 1);
  shared_.clock = clock_;
  shared_.scheduler = scheduler_.get();
  if (options_.trace) {
    trace_ = std::make_unique<TraceRecorder>(threads, std::size_t{1} << 20);
    shared_.trace = trace_.get();
  }
  shared_.fail = [this](const std::string& error) { fail(error); };
  shared_.node_finished = [this](bool source, bool daemon) { node_finished(source, daemon); };
  watchdog_ = std::make_unique<Watchdog>(*clock_, [this](const WatchdogEvent& e) { on_watchdog_event(e); });

  for (std::size_t i = 0; i < n; ++i) {
    const NodeConfig& nc = config_.nodes[i];
    Contract& c = *decl[i].contract;
    auto rt = std::make_unique<detail::NodeRuntime>(
        static_cast<int>(i), nc.name, nc.type, decl[i].type->create(), c.resolved_options(),
        nc.input_policy.value_or(c.input_policy()), c.daemon(), shared_);
    for (const PortSpec& p : c.inputs()) rt->inputs.push_back({p.name, p.type, nullptr, false});
    for (std::size_t p = 0; p < c.outputs().size(); ++p) {
      detail::OutputPort port;
      port.name = c.outputs()[p].name;
      port.type = decl[i].out_type[p];
      rt->outputs.push_back(std::move(port));
    }
    if (nc.watchdog.watches_anything()) {
      watchdog_->watch("node " + nc.name, nc.watchdog, &rt->watch_point());
    }
    if (nc.type == "WatchdogEvents") event_nodes_.push_back(rt.get());
    nodes_.push_back(std::move(rt));
  }
  for (std::size_t s = 0; s < wires.size(); ++s) {
    const StreamConfig& sc = config_.streams[s];
    const Wire& w = wires[s];
    auto stream = std::make_unique<Stream>(sc.from + " -> " + sc.to, sc.options, *clock_);
    detail::NodeRuntime* from = nodes_[static_cast<std::size_t>(w.from_node)].get();
    detail::NodeRuntime* to = nodes_[static_cast<std::size_t>(w.to_node)].get();
    stream->connect(from, to);
    from->outputs[static_cast<std::size_t>(w.from_port)].streams.push_back(stream.get());
    detail::InputSlot& slot = to->inputs[static_cast<std::size_t>(w.to_port)];
    slot.stream = stream.get();
    slot.back_edge = sc.options.back_edge;
    if (sc.watchdog.watches_anything() || sc.options.max_consecutive_drops > 0) {
      watchdog_->watch("stream " + stream->name(), sc.watchdog, &stream->watch_point());
    }
    streams_.push_back(std::move(stream));
  }
}

detail::NodeRuntime* Graph::find_node(std::string_view name) const {
  for (const auto& rt : nodes_) {
    if (rt->name() == name) return rt.get();
  }
  return nullptr;
}

void Graph::observe(std::string_view output, PacketObserver observer) {
  Endpoint e;
  detail::NodeRuntime* rt = split_endpoint(std::string(output), e) ? find_node(e.node) : nullptr;
  if (rt) {
    for (detail::OutputPort& p : rt->outputs) {
      if (p.name == e.port) {
        p.observers.push_back(std::move(observer));
        return;
      }
    }
  }
  throw GraphError("observe: no output port '" + std::string(output) + "'");
}

void Graph::start() {
  {
    std::lock_guard lock(mutex_);
    if (started_) throw GraphError("graph: start() called twice");
  }
  for (std::size_t i = 0; i < nodes_.size(); ++i) {
    try {
      nodes_[i]->open();
    } catch (...) {
      for (std::size_t j = i; j-- > 0;) nodes_[j]->close_if_open();
      throw;
    }
  }
  int sources = 0;
  for (const auto& rt : nodes_) {
    if (rt->is_source() && !rt->daemon()) ++sources;
  }
  {
    std::lock_guard lock(mutex_);
    started_ = true;
    remaining_ = static_cast<int>(nodes_.size());
    finished_ = remaining_ == 0;
  }
  shared_.live_sources.store(sources, std::memory_order_release);
  watchdog_->arm();
  if (options_.watchdog_thread) {
    watchdog_->start(std::chrono::milliseconds(config_.watchdog_interval_ms));
  }
  scheduler_->start();
  for (const auto& rt : nodes_) rt->wake();
}

void Graph::fail(const std::string& error) {
  {
    std::lock_guard lock(mutex_);
    if (error_.empty()) error_ = error;
    finished_ = true;
  }
  shared_.cancelled.store(true, std::memory_order_release);
  marvin::log(LogLevel::kError, "graph", error);
  finished_cv_.notify_all();
}

void Graph::node_finished(bool source, bool daemon) {
  if (source && !daemon && shared_.live_sources.fetch_sub(1, std::memory_order_acq_rel) == 1) {
    // The last real source is done: daemon sources (event relays) may finish too.
    for (const auto& rt : nodes_) {
      if (rt->daemon()) rt->wake();
    }
  }
  bool all_done = false;
  {
    std::lock_guard lock(mutex_);
    all_done = --remaining_ == 0;
    if (all_done) finished_ = true;
  }
  if (all_done) finished_cv_.notify_all();
}

void Graph::push(std::string_view input, Packet packet) {
  detail::NodeRuntime* rt = find_node(input);
  auto* node = rt ? dynamic_cast<GraphInputNode*>(rt->node()) : nullptr;
  if (!node) throw GraphError("push: no GraphInput node named '" + std::string(input) + "'");
  node->enqueue(std::move(packet));
  rt->wake();
}

void Graph::close_input(std::string_view input) {
  detail::NodeRuntime* rt = find_node(input);
  auto* node = rt ? dynamic_cast<GraphInputNode*>(rt->node()) : nullptr;
  if (!node) throw GraphError("close_input: no GraphInput node named '" + std::string(input) + "'");
  node->close_input();
  rt->wake();
}

void Graph::stop() {
  shared_.stop_requested.store(true, std::memory_order_release);
  for (const auto& rt : nodes_) {
    if (rt->is_source()) rt->wake();
  }
}

void Graph::cancel() {
  shared_.cancelled.store(true, std::memory_order_release);
  {
    std::lock_guard lock(mutex_);
    finished_ = true;
  }
  finished_cv_.notify_all();
}

void Graph::on_watchdog_event(const WatchdogEvent& event) {
  marvin::log(LogLevel::kWarning, "graph", "watchdog: " + event.message);
  for (detail::NodeRuntime* rt : event_nodes_) {
    static_cast<WatchdogEventsNode*>(rt->node())->enqueue(event);
    rt->wake();
  }
}

void Graph::join() {
  {
    std::lock_guard lock(mutex_);
    if (joined_) return;
    joined_ = true;
  }
  scheduler_->stop();
  watchdog_->stop();
  for (auto it = nodes_.rbegin(); it != nodes_.rend(); ++it) (*it)->close_if_open();
}

void Graph::wait() {
  {
    std::unique_lock lock(mutex_);
    if (!started_) throw GraphError("graph: wait() before start()");
    finished_cv_.wait(lock, [this] { return finished_; });
  }
  join();
  std::lock_guard lock(mutex_);
  if (!error_.empty()) throw GraphError(error_);
}

bool Graph::wait_for(std::chrono::nanoseconds timeout) {
  {
    std::unique_lock lock(mutex_);
    if (!started_) throw GraphError("graph: wait_for() before start()");
    if (!finished_cv_.wait_for(lock, timeout, [this] { return finished_; })) return false;
  }
  wait();
  return true;
}

GraphStats Graph::stats() const {
  GraphStats s;
  for (const auto& rt : nodes_) s.nodes.push_back(rt->stats());
  for (const auto& st : streams_) s.streams.push_back(st->stats());
  s.watchdog_events = watchdog_->event_count();
  return s;
}

std::string Graph::to_dot() const {
  auto quote = [](const std::string& s) { return nlohmann::json(s).dump(); };
  std::string out = "digraph marvin_graph {\n  rankdir=LR;\n  node [shape=box];\n";
  for (const auto& rt : nodes_) {
    out += "  " + quote(rt->name()) + " [label=" + quote(rt->name() + "\n" + rt->type()) + "];\n";
  }
  for (const auto& rt : nodes_) {
    for (const detail::OutputPort& o : rt->outputs) {
      for (const Stream* s : o.streams) {
        const StreamOptions& so = s->options();
        std::string consumer, port;
        for (const auto& c : nodes_) {
          for (const detail::InputSlot& in : c->inputs) {
            if (in.stream == s) {
              consumer = c->name();
              port = in.name;
            }
          }
        }
        std::string label = o.name + " -> " + port + "\n" + o.type + ", " +
                            to_string(so.policy) + "(" + std::to_string(so.capacity) + ")";
        out += "  " + quote(rt->name()) + " -> " + quote(consumer) + " [label=" + quote(label) +
               (so.back_edge ? ", style=dashed" : "") + "];\n";
      }
    }
  }
  out += "}\n";
  return out;
}

void Graph::write_trace(const std::string& path) const {
  if (!trace_) throw GraphError("write_trace: the graph was not started with tracing on");
  std::vector<std::string> names;
  for (const auto& rt : nodes_) names.push_back(rt->name());
  trace_->write_chrome_trace(path, names);
}

}  // namespace marvin::graph
