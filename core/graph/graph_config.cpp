#include "graph/graph_config.h"

#include <cmath>
#include <fstream>
#include <set>
#include <sstream>

namespace marvin::graph {

GraphConfig& GraphConfig::add_node(std::string name, std::string type, nlohmann::json options) {
  NodeConfig n;
  n.name = std::move(name);
  n.type = std::move(type);
  n.options = std::move(options);
  nodes.push_back(std::move(n));
  return *this;
}

GraphConfig& GraphConfig::connect(std::string from, std::string to, StreamOptions options) {
  StreamConfig s;
  s.from = std::move(from);
  s.to = std::move(to);
  s.options = options;
  streams.push_back(std::move(s));
  return *this;
}

namespace {

using nlohmann::json;

class Reader {
 public:
  explicit Reader(std::string origin) : origin_(std::move(origin)) {}

  [[noreturn]] void fail(const std::string& path, const std::string& message) const {
    throw GraphError(origin_ + ": " + path + (path.empty() ? "" : ": ") + message);
  }

  void expect_object(const json& j, const std::string& path) const {
    if (!j.is_object()) fail(path, "expected a JSON object, got " + j.dump());
  }

  void only_keys(const json& j, const std::string& path, const std::set<std::string>& keys) const {
    for (auto it = j.begin(); it != j.end(); ++it) {
      if (!keys.count(it.key())) {
        std::string list;
        for (const auto& k : keys) list += (list.empty() ? "" : ", ") + k;
        fail(path, "unknown field '" + it.key() + "' (expected one of: " + list + ")");
      }
    }
  }

  std::string string_field(const json& j, const std::string& path, const char* key,
                           bool required) const {
    auto it = j.find(key);
    if (it == j.end()) {
      if (required) fail(path, std::string("missing field \"") + key + "\"");
      return {};
    }
    if (!it->is_string() || it->get<std::string>().empty()) {
      fail(path + "." + key, "expected a non-empty string, got " + it->dump());
    }
    return it->get<std::string>();
  }

  int64_t int_field(const json& j, const std::string& path, const char* key, int64_t fallback,
                    int64_t min, int64_t max) const {
    auto it = j.find(key);
    if (it == j.end()) return fallback;
    if (!it->is_number_integer()) fail(path + "." + key, "expected an integer, got " + it->dump());
    const auto v = it->get<int64_t>();
    if (v < min || v > max) {
      fail(path + "." + key, "must be in [" + std::to_string(min) + ", " + std::to_string(max) +
                                 "], got " + std::to_string(v));
    }
    return v;
  }

  double number_field(const json& j, const std::string& path, const char* key) const {
    auto it = j.find(key);
    if (it == j.end()) return 0;
    if (!it->is_number() || it->get<double>() < 0 || !std::isfinite(it->get<double>())) {
      fail(path + "." + key, "expected a number >= 0, got " + it->dump());
    }
    return it->get<double>();
  }

  WatchSpec watch_spec(const json& j, const std::string& path) const {
    expect_object(j, path);
    only_keys(j, path,
              {"deadline_ms", "max_latency_ms", "min_rate_hz", "max_rate_hz", "rate_window_ms"});
    WatchSpec w;
    auto to_ns = [](double ms) { return static_cast<int64_t>(std::llround(ms * 1e6)); };
    w.deadline_ns = to_ns(number_field(j, path, "deadline_ms"));
    w.max_latency_ns = to_ns(number_field(j, path, "max_latency_ms"));
    w.min_rate_hz = number_field(j, path, "min_rate_hz");
    w.max_rate_hz = number_field(j, path, "max_rate_hz");
    if (j.contains("rate_window_ms")) {
      w.rate_window_ns = to_ns(number_field(j, path, "rate_window_ms"));
      if (w.rate_window_ns <= 0) fail(path + ".rate_window_ms", "must be above 0");
    }
    if (w.min_rate_hz > 0 && w.max_rate_hz > 0 && w.min_rate_hz > w.max_rate_hz) {
      fail(path, "min_rate_hz is above max_rate_hz");
    }
    return w;
  }

  NodeConfig node(const json& j, const std::string& path) const {
    expect_object(j, path);
    only_keys(j, path, {"name", "type", "options", "input_policy", "watchdog"});
    NodeConfig n;
    n.name = string_field(j, path, "name", true);
    n.type = string_field(j, path, "type", true);
    if (auto it = j.find("options"); it != j.end()) {
      expect_object(*it, path + ".options");
      n.options = *it;
    }
    const std::string policy = string_field(j, path, "input_policy", false);
    if (policy == "synchronized") {
      n.input_policy = InputPolicy::kSynchronized;
    } else if (policy == "immediate") {
      n.input_policy = InputPolicy::kImmediate;
    } else if (!policy.empty()) {
      fail(path + ".input_policy", "must be \"synchronized\" or \"immediate\", got \"" + policy + "\"");
    }
    if (auto it = j.find("watchdog"); it != j.end()) n.watchdog = watch_spec(*it, path + ".watchdog");
    return n;
  }

  StreamConfig stream(const json& j, const std::string& path) const {
    expect_object(j, path);
    only_keys(j, path, {"from", "to", "policy", "capacity", "max_consecutive_drops", "back_edge",
                        "watchdog"});
    StreamConfig s;
    s.from = string_field(j, path, "from", true);
    s.to = string_field(j, path, "to", true);
    const std::string policy = string_field(j, path, "policy", false);
    if (policy.empty() || policy == "lossless") {
      s.options.policy = StreamPolicy::kLossless;
    } else if (policy == "drop_oldest") {
      s.options.policy = StreamPolicy::kDropOldest;
    } else if (policy == "drop_newest") {
      s.options.policy = StreamPolicy::kDropNewest;
    } else {
      fail(path + ".policy",
           "must be \"lossless\", \"drop_oldest\" or \"drop_newest\", got \"" + policy + "\"");
    }
    s.options.capacity = static_cast<std::size_t>(int_field(j, path, "capacity", 64, 1, 1 << 20));
    s.options.max_consecutive_drops = static_cast<uint32_t>(
        int_field(j, path, "max_consecutive_drops", 0, 0, UINT32_MAX));
    if (s.options.policy == StreamPolicy::kLossless && s.options.max_consecutive_drops > 0) {
      fail(path + ".max_consecutive_drops", "only applies to drop_oldest/drop_newest streams");
    }
    if (auto it = j.find("back_edge"); it != j.end()) {
      if (!it->is_boolean()) fail(path + ".back_edge", "expected true or false, got " + it->dump());
      s.options.back_edge = it->get<bool>();
    }
    if (auto it = j.find("watchdog"); it != j.end()) s.watchdog = watch_spec(*it, path + ".watchdog");
    return s;
  }

 private:
  std::string origin_;
};

}  // namespace

GraphConfig parse_graph_config(const json& j, const std::string& origin) {
  Reader r(origin);
  r.expect_object(j, "");
  r.only_keys(j, "", {"threads", "watchdog_interval_ms", "nodes", "streams", "description"});
  GraphConfig g;
  g.threads = static_cast<int>(r.int_field(j, "", "threads", 2, 1, 256));
  g.watchdog_interval_ms = r.int_field(j, "", "watchdog_interval_ms", 100, 1, 3'600'000);
  auto nodes = j.find("nodes");
  if (nodes == j.end()) r.fail("", "missing field \"nodes\"");
  if (!nodes->is_array()) r.fail("nodes", "expected an array, got " + nodes->dump());
  for (std::size_t i = 0; i < nodes->size(); ++i) {
    g.nodes.push_back(r.node((*nodes)[i], "nodes[" + std::to_string(i) + "]"));
  }
  if (auto streams = j.find("streams"); streams != j.end()) {
    if (!streams->is_array()) r.fail("streams", "expected an array, got " + streams->dump());
    for (std::size_t i = 0; i < streams->size(); ++i) {
      g.streams.push_back(r.stream((*streams)[i], "streams[" + std::to_string(i) + "]"));
    }
  }
  return g;
}

GraphConfig load_graph_config(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw GraphError(path + ": cannot open the file");
  std::stringstream text;
  text << in.rdbuf();
  json j;
  try {
    j = json::parse(text.str());
  } catch (const json::parse_error& e) {
    throw GraphError(path + ": not valid JSON (byte " + std::to_string(e.byte) + "): " + e.what());
  }
  return parse_graph_config(j, path);
}

}  // namespace marvin::graph
