#include "graph/contract.h"

#include <algorithm>

namespace marvin::graph {

const char* to_string(InputPolicy policy) {
  return policy == InputPolicy::kSynchronized ? "synchronized" : "immediate";
}

const nlohmann::json& Options::at(const std::string& name) const {
  auto it = values_.find(name);
  if (it == values_.end()) throw ContractError("option '" + name + "' was not declared");
  return *it;
}

int64_t Options::get_int(const std::string& name) const {
  const auto& v = at(name);
  if (!v.is_number_integer()) throw ContractError("option '" + name + "' is not an integer");
  return v.get<int64_t>();
}

double Options::get_double(const std::string& name) const {
  const auto& v = at(name);
  if (!v.is_number()) throw ContractError("option '" + name + "' is not a number");
  return v.get<double>();
}

bool Options::get_bool(const std::string& name) const {
  const auto& v = at(name);
  if (!v.is_boolean()) throw ContractError("option '" + name + "' is not a boolean");
  return v.get<bool>();
}

std::string Options::get_string(const std::string& name) const {
  const auto& v = at(name);
  if (!v.is_string()) throw ContractError("option '" + name + "' is not a string");
  return v.get<std::string>();
}

Contract::Contract(nlohmann::json given) : given_(std::move(given)) {
  if (given_.is_null()) given_ = nlohmann::json::object();
  if (!given_.is_object()) throw ContractError("options must be a JSON object, got " + given_.dump());
}

int Contract::add_input(std::string name, std::string type, bool optional) {
  inputs_.push_back({std::move(name), std::move(type), optional});
  return static_cast<int>(inputs_.size() - 1);
}

int Contract::add_output(std::string name, std::string type) {
  outputs_.push_back({std::move(name), std::move(type), false});
  return static_cast<int>(outputs_.size() - 1);
}

const nlohmann::json* Contract::given(const std::string& name) {
  auto it = given_.find(name);
  return it == given_.end() ? nullptr : &*it;
}

int64_t Contract::option_int(const std::string& name, int64_t fallback, int64_t min, int64_t max) {
  int64_t value = fallback;
  if (const auto* v = given(name)) {
    if (!v->is_number_integer()) {
      throw ContractError("option '" + name + "' must be an integer, got " + v->dump());
    }
    value = v->get<int64_t>();
  }
  if (value < min || value > max) {
    throw ContractError("option '" + name + "' must be in [" + std::to_string(min) + ", " +
                        std::to_string(max) + "], got " + std::to_string(value));
  }
  resolved_[name] = value;
  return value;
}

double Contract::option_double(const std::string& name, double fallback, double min, double max) {
  double value = fallback;
  if (const auto* v = given(name)) {
    if (!v->is_number()) throw ContractError("option '" + name + "' must be a number, got " + v->dump());
    value = v->get<double>();
  }
  if (value < min || value > max) {
    throw ContractError("option '" + name + "' must be in [" + nlohmann::json(min).dump() + ", " +
                        nlohmann::json(max).dump() + "], got " + nlohmann::json(value).dump());
  }
  resolved_[name] = value;
  return value;
}

bool Contract::option_bool(const std::string& name, bool fallback) {
  bool value = fallback;
  if (const auto* v = given(name)) {
    if (!v->is_boolean()) throw ContractError("option '" + name + "' must be true or false, got " + v->dump());
    value = v->get<bool>();
  }
  resolved_[name] = value;
  return value;
}

std::string Contract::option_string(const std::string& name, std::string fallback,
                                    const std::vector<std::string>& choices) {
  std::string value = std::move(fallback);
  if (const auto* v = given(name)) {
    if (!v->is_string()) throw ContractError("option '" + name + "' must be a string, got " + v->dump());
    value = v->get<std::string>();
  }
  if (!choices.empty() && std::find(choices.begin(), choices.end(), value) == choices.end()) {
    std::string list;
    for (const auto& c : choices) list += (list.empty() ? "" : ", ") + c;
    throw ContractError("option '" + name + "' must be one of " + list + ", got '" + value + "'");
  }
  resolved_[name] = value;
  return value;
}

void Contract::check_no_unknown_options() const {
  for (auto it = given_.begin(); it != given_.end(); ++it) {
    if (!resolved_.contains(it.key())) {
      std::string known;
      for (auto r = resolved_.begin(); r != resolved_.end(); ++r) known += (known.empty() ? "" : ", ") + r.key();
      throw ContractError("unknown option '" + it.key() + "' (known: " +
                          (known.empty() ? "none" : known) + ")");
    }
  }
}

}  // namespace marvin::graph
