// GraphConfig: the description of a graph, as plain data, and its JSON form.
//
// A graph file looks like this (every field but "nodes" is optional):
//
//   {
//     "threads": 2,                           worker threads (CLI --threads overrides)
//     "watchdog_interval_ms": 100,            how often the watchdog checks
//     "nodes": [
//       {"name": "mic", "type": "SyntheticAudioSource",
//        "options": {"chunk_ms": 20},         declared by the node type (see its header)
//        "input_policy": "synchronized",      or "immediate"; default: the type's choice
//        "watchdog": {"max_latency_ms": 5}}   see watchdog.h
//     ],
//     "streams": [
//       {"from": "mic.out", "to": "agg.in",   "node.port" at both ends
//        "policy": "lossless",                or "drop_oldest" / "drop_newest"
//        "capacity": 64, "max_consecutive_drops": 0, "back_edge": false,
//        "watchdog": {"deadline_ms": 200}}
//     ]
//   }
//
// Parsing checks the shape of the file (fields, their JSON types, unknown keys); what the
// nodes and ports mean is checked when a Graph is built from the config (graph.h). Errors
// throw GraphError naming the file and the JSON path ("demo.json: streams[2].policy: ...").
// Graphs can equally be built in code by filling these structs.
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "graph/contract.h"
#include "graph/stream.h"
#include "graph/watchdog.h"

namespace marvin::graph {

// Every error about a graph: its file, its wiring, its options, or a node failing at run time.
class GraphError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct NodeConfig {
  std::string name;
  std::string type;
  nlohmann::json options = nlohmann::json::object();
  std::optional<InputPolicy> input_policy;  // unset: the node type's default
  WatchSpec watchdog;
};

struct StreamConfig {
  std::string from;  // "node.port"
  std::string to;    // "node.port"
  StreamOptions options;
  WatchSpec watchdog;
};

struct GraphConfig {
  std::vector<NodeConfig> nodes;
  std::vector<StreamConfig> streams;
  int threads = 2;
  int64_t watchdog_interval_ms = 100;

  // Conveniences for graphs built in code. Return *this for chaining.
  GraphConfig& add_node(std::string name, std::string type,
                        nlohmann::json options = nlohmann::json::object());
  GraphConfig& connect(std::string from, std::string to, StreamOptions options = {});
};

// Parses a graph from JSON; `origin` (a file name) prefixes every error.
GraphConfig parse_graph_config(const nlohmann::json& json, const std::string& origin);
// Reads and parses a graph file. Throws GraphError if it cannot be read or parsed.
GraphConfig load_graph_config(const std::string& path);

}  // namespace marvin::graph
