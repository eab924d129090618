// NodeRegistry: node types by name, so a graph can be data.
//
// MARVIN_REGISTER_NODE(Class, "Name") at namespace scope in the node's .cpp registers it at
// program start. The built-in nodes (latch.h, aggregator.h, builtin_nodes.h) are registered
// when the registry is first used, so linking marvin_graph statically never loses them.
// Thread-safe.
#pragma once

#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <string_view>
#include <vector>

namespace marvin::graph {

class Contract;
class Node;

struct NodeType {
  std::string name;
  void (*declare)(Contract&);
  std::unique_ptr<Node> (*create)();
};

class NodeRegistry {
 public:
  // The process-wide registry (with the built-in nodes).
  static NodeRegistry& global();

  // Adds a type; throws std::logic_error if the name is taken.
  void add(NodeType type);
  // Null when unknown.
  const NodeType* find(std::string_view name) const;
  // Sorted.
  std::vector<std::string> names() const;

 private:
  NodeRegistry() = default;
  mutable std::mutex mutex_;
  std::map<std::string, NodeType, std::less<>> types_;
};

namespace detail {
void register_builtin_nodes(NodeRegistry& registry);
}

template <typename N>
struct NodeRegistration {
  explicit NodeRegistration(const char* name) {
    NodeRegistry::global().add(
        {name, &N::declare, []() -> std::unique_ptr<Node> { return std::make_unique<N>(); }});
  }
};

}  // namespace marvin::graph

#define MARVIN_GRAPH_CONCAT_INNER(a, b) a##b
#define MARVIN_GRAPH_CONCAT(a, b) MARVIN_GRAPH_CONCAT_INNER(a, b)
// Registers node class `Class` under the graph type name `Name` (a string literal).
#define MARVIN_REGISTER_NODE(Class, Name)                                             \
  static const ::marvin::graph::NodeRegistration<Class> MARVIN_GRAPH_CONCAT( \
      marvin_node_registration_, __COUNTER__)(Name)
