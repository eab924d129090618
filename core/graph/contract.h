// Contract: what a node type declares about itself before any instance runs.
//
// Each node class has a static `declare(Contract&)` (see node.h) that the graph calls while it
// is built, with the options given in the graph. It declares
//
//   - input and output ports, each with a packet type name (see packet.h). Ports are numbered
//     in declaration order per direction; process() addresses them by that index. A port
//     type may also be "any" (accepts every type) or, for an output, "same_as:<input>" (the
//     type of whatever is connected to that input, resolved when the graph is built).
//   - options, each with a type, a default and a valid range. Declaring an option returns its
//     value for this instance, so ports can depend on options (a Latch with N channels).
//     Options the graph gives but the contract does not declare are errors.
//   - the default input policy (synchronized by timestamp, or immediate).
//
// Errors (bad option value, unknown option) throw ContractError; the graph adds the node's name.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "graph/packet.h"

namespace marvin::graph {

class ContractError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// How a node with several inputs is fed.
enum class InputPolicy {
  // process() sees, at once, every input's packet for the smallest pending timestamp; it is
  // called only when every input either has a packet at that timestamp or its bound has
  // passed it. Inputs without a packet at that timestamp are empty in that call.
  kSynchronized,
  // process() is called with one packet at a time, from whichever input has one (smallest
  // timestamp first). The node must keep its own outputs' timestamps increasing.
  kImmediate,
};

// "synchronized", "immediate".
const char* to_string(InputPolicy policy);

struct PortSpec {
  std::string name;
  std::string type;        // packet type name, "any", or "same_as:<input>" (outputs)
  bool optional = false;   // inputs only: may stay unconnected
};

// The resolved options of one node instance: given values merged over declared defaults.
class Options {
 public:
  Options() = default;
  explicit Options(nlohmann::json values) : values_(std::move(values)) {}
  // These throw ContractError if `name` was not declared with that type.
  int64_t get_int(const std::string& name) const;
  double get_double(const std::string& name) const;
  bool get_bool(const std::string& name) const;
  std::string get_string(const std::string& name) const;
  const nlohmann::json& json() const { return values_; }

 private:
  const nlohmann::json& at(const std::string& name) const;
  nlohmann::json values_ = nlohmann::json::object();
};

class Contract {
 public:
  // `given` is the node's "options" object from the graph (may be null or empty).
  explicit Contract(nlohmann::json given);

  // Port declarations; each returns the port's index.
  int add_input(std::string name, std::string type, bool optional = false);
  int add_output(std::string name, std::string type);
  template <typename T>
  int add_input(std::string name, bool optional = false) {
    return add_input(std::move(name), packet_type_name<T>(), optional);
  }
  template <typename T>
  int add_output(std::string name) {
    return add_output(std::move(name), packet_type_name<T>());
  }

  // Option declarations: return the value given in the graph, or the default. Values outside
  // [min, max] or of the wrong JSON type throw ContractError naming the option.
  int64_t option_int(const std::string& name, int64_t fallback, int64_t min = INT64_MIN,
                     int64_t max = INT64_MAX);
  double option_double(const std::string& name, double fallback, double min = -1e300,
                       double max = 1e300);
  bool option_bool(const std::string& name, bool fallback);
  // `choices` empty means any string.
  std::string option_string(const std::string& name, std::string fallback,
                            const std::vector<std::string>& choices = {});

  void set_input_policy(InputPolicy policy) { input_policy_ = policy; }
  // For sources that only relay events (WatchdogEvents): the node is asked to stop once every
  // other source has finished, so it does not keep a finished graph alive.
  void set_daemon() { daemon_ = true; }

  // ---- read by the graph ----
  const std::vector<PortSpec>& inputs() const { return inputs_; }
  const std::vector<PortSpec>& outputs() const { return outputs_; }
  InputPolicy input_policy() const { return input_policy_; }
  bool daemon() const { return daemon_; }
  // Throws ContractError for given options that were never declared.
  void check_no_unknown_options() const;
  Options resolved_options() const { return Options(resolved_); }

 private:
  const nlohmann::json* given(const std::string& name);
  nlohmann::json given_;
  nlohmann::json resolved_ = nlohmann::json::object();
  std::vector<PortSpec> inputs_, outputs_;
  InputPolicy input_policy_ = InputPolicy::kSynchronized;
  bool daemon_ = false;
};

}  // namespace marvin::graph
