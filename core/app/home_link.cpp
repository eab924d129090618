#include "app/home_link.h"

#include "home/discovery.h"

namespace marvin::app {

using nlohmann::json;

json device_json(const home::Device& d) {
  json out{{"id", d.id},
           {"name", d.name},
           {"room", d.room},
           {"type", home::type_name(d.type)},
           {"dimmable", d.dimmable},
           {"aliases", d.aliases},
           {"available", d.state.available},
           {"on", d.state.on ? json(*d.state.on) : json()},
           {"brightness", d.state.brightness_pct ? json(*d.state.brightness_pct) : json()}};
  if (d.type == home::DeviceType::kThermostat) {
    out["target_temperature"] = d.state.target_c ? json(*d.state.target_c) : json();
    out["temperature"] = d.state.current_c ? json(*d.state.current_c) : json();
    out["min_temperature"] = d.protocol.min_c;
    out["max_temperature"] = d.protocol.max_c;
    out["switchable"] = !d.protocol.heat_mode.empty();
  }
  return out;
}

json HomeLink::devices() {
  json list = json::array();
  for (const home::Device& d : service_.devices()) list.push_back(device_json(d));
  return json{{"connected", service_.connected()}, {"room", service_.room()}, {"devices", list}};
}

skills::SmartHome::Reply HomeLink::set(const std::string& device, const json& state) {
  Reply reply;
  // An id, else the one device with that name or alias.
  const std::string wanted = home::lower(device);
  std::vector<home::Device> found;
  for (home::Device& d : service_.devices()) {
    bool named = d.id == device || d.name == wanted;
    for (const std::string& a : d.aliases) named = named || a == wanted;
    if (named) found.push_back(std::move(d));
  }
  if (found.size() != 1) {
    reply.result = Result::kNotFound;
    reply.sentence = found.empty() ? "there is no device \"" + device + "\""
                                   : "\"" + device + "\" names " + std::to_string(found.size()) +
                                         " devices; use an id from smarthome_devices";
    return reply;
  }
  const home::Device& d = found.front();
  home::DeviceCommand command;
  const bool thermostat = d.type == home::DeviceType::kThermostat;
  if (state.contains("on")) {
    if (thermostat && d.protocol.heat_mode.empty()) {
      reply.result = Result::kInvalid;
      reply.sentence = "the " + d.name + " cannot be switched on or off, only set to a temperature";
      return reply;
    }
    command.on = state["on"].get<bool>();
  }
  if (state.contains("target_temperature")) {
    const double target = state["target_temperature"].get<double>();
    if (!thermostat) {
      reply.result = Result::kInvalid;
      reply.sentence = "the " + d.name + " is not a thermostat";
      return reply;
    }
    if (target < d.protocol.min_c || target > d.protocol.max_c) {
      reply.result = Result::kInvalid;
      reply.sentence = "the " + d.name + " can be set from " + home::celsius_text(d.protocol.min_c) +
                       " to " + home::celsius_text(d.protocol.max_c) + " degrees";
      return reply;
    }
    command.target_c = target;
  }
  if (state.contains("brightness")) {
    if (!d.dimmable) {
      reply.result = Result::kInvalid;
      reply.sentence = "the " + d.name + " cannot be dimmed";
      return reply;
    }
    command.brightness_pct = state["brightness"].get<int>();
  }
  service_.publish_activity("acting");
  home::HomeService::SetResult r = service_.set(d.id, command);
  service_.publish_activity("listening");
  home::Device now = d;
  now.state = r.state;
  reply.device = device_json(now);
  const auto& broker = service_.config().broker;
  switch (r.outcome) {
    case home::HomeService::Outcome::kConfirmed:
      reply.result = Result::kDone;
      break;
    case home::HomeService::Outcome::kNoAnswer:
      reply.result = Result::kUnavailable;
      reply.sentence = "the " + d.name + " did not report the new state within " +
                       std::to_string(service_.config().answer_timeout.count()) + " ms";
      break;
    case home::HomeService::Outcome::kDeviceOffline:
      reply.result = Result::kUnavailable;
      reply.sentence = "the " + d.name + " is offline";
      break;
    case home::HomeService::Outcome::kBrokerUnreachable:
      reply.result = Result::kUnavailable;
      reply.sentence = "the home's broker " + broker.host + ":" + std::to_string(broker.port) +
                       " is unreachable (reconnecting in the background)";
      break;
    case home::HomeService::Outcome::kUnknownDevice:
      reply.result = Result::kNotFound;
      reply.sentence = "the " + d.name + " is gone from the home's device list";
      break;
  }
  return reply;
}

}  // namespace marvin::app
