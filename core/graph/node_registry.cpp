#include "graph/node_registry.h"

#include <stdexcept>

#include "graph/node.h"

namespace marvin::graph {

NodeRegistry& NodeRegistry::global() {
  static NodeRegistry* registry = [] {
    auto* r = new NodeRegistry;  // never destroyed: registrations may run during static init
    detail::register_builtin_nodes(*r);
    return r;
  }();
  return *registry;
}

void NodeRegistry::add(NodeType type) {
  std::lock_guard lock(mutex_);
  std::string name = type.name;
  if (!types_.emplace(name, std::move(type)).second) {
    throw std::logic_error("node type '" + name + "' is registered twice");
  }
}

const NodeType* NodeRegistry::find(std::string_view name) const {
  std::lock_guard lock(mutex_);
  auto it = types_.find(name);
  return it == types_.end() ? nullptr : &it->second;
}

std::vector<std::string> NodeRegistry::names() const {
  std::lock_guard lock(mutex_);
  std::vector<std::string> out;
  for (const auto& [name, type] : types_) out.push_back(name);
  return out;
}

}  // namespace marvin::graph
