#include "home/discovery.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <nlohmann/json.hpp>
#include <tuple>

namespace marvin::home {
namespace {

using nlohmann::json;

json parse(std::string_view payload, const char* what) {
  try {
    return json::parse(payload);
  } catch (const json::parse_error& e) {
    throw DiscoveryError(std::string(what) + " is not valid JSON at byte " +
                         std::to_string(e.byte));
  }
}

// A string member under its full or abbreviated Home Assistant key ("" if absent).
std::string member(const json& object, const char* key, const char* abbreviation = nullptr) {
  for (const char* k : {key, abbreviation}) {
    if (!k) continue;
    auto it = object.find(k);
    if (it == object.end() || it->is_null()) continue;
    if (!it->is_string()) {
      throw DiscoveryError(std::string("\"") + k + "\" must be a string, got " + it->dump());
    }
    return it->get<std::string>();
  }
  return "";
}

// "~/set" with "~": "home/kitchen" -> "home/kitchen/set" (HA's base-topic abbreviation).
std::string expand(const std::string& topic, const std::string& base) {
  if (base.empty()) return topic;
  if (!topic.empty() && topic.front() == '~') return base + topic.substr(1);
  if (!topic.empty() && topic.back() == '~') return topic.substr(0, topic.size() - 1) + base;
  return topic;
}

int clamp_pct(double value) { return static_cast<int>(std::clamp(std::lround(value), 0L, 100L)); }

int to_pct(double raw, int max) { return clamp_pct(raw * 100.0 / std::max(1, max)); }
int from_pct(int pct, int max) {
  return static_cast<int>(std::lround(std::clamp(pct, 0, 100) * max / 100.0));
}

std::optional<bool> on_of(const std::string& text, const std::string& on, const std::string& off) {
  if (text == on) return true;
  if (text == off) return false;
  std::string l = lower(text);
  if (l == "on" || l == "true") return true;
  if (l == "off" || l == "false") return false;
  return std::nullopt;
}

// A number member under its full or abbreviated key; `fallback` if absent.
double number(const json& object, const char* key, const char* abbreviation, double fallback) {
  for (const char* k : {key, abbreviation}) {
    if (!k) continue;
    auto it = object.find(k);
    if (it == object.end() || it->is_null()) continue;
    if (!it->is_number()) {
      throw DiscoveryError(std::string("\"") + k + "\" must be a number, got " + it->dump());
    }
    return it->get<double>();
  }
  return fallback;
}

// The mode that means "heating on" among a thermostat's modes: "heat", else the first one
// that is not "off"; "" when it has none (it cannot be switched off, only set).
std::string heat_mode_of(const json& modes) {
  if (!modes.is_array()) return "";
  std::string first;
  for (const json& m : modes) {
    if (!m.is_string()) continue;
    if (m == "heat") return "heat";
    if (first.empty() && m != "off") first = m.get<std::string>();
  }
  return first;
}

// A plain temperature payload ("21.5"); nullopt if it is not one.
std::optional<double> celsius_of(std::string_view payload) {
  std::string text(payload);
  char* end = nullptr;
  double value = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size() || !std::isfinite(value)) return std::nullopt;
  return value;
}

// A Home Assistant "climate": the mode on the command/state topics, the set point and the
// measured temperature on their own (plain payloads, no templates).
void read_ha_climate(const json& config, const std::string& base, Device* d) {
  DeviceProtocol& p = d->protocol;
  p.dialect = DeviceProtocol::Dialect::kHaDefault;
  p.setpoint_command_topic = expand(member(config, "temperature_command_topic", "temp_cmd_t"), base);
  if (p.setpoint_command_topic.empty())
    throw DiscoveryError("\"temperature_command_topic\" is missing");
  p.setpoint_state_topic = expand(member(config, "temperature_state_topic", "temp_stat_t"), base);
  p.current_temperature_topic =
      expand(member(config, "current_temperature_topic", "curr_temp_t"), base);
  p.command_topic = expand(member(config, "mode_command_topic", "mode_cmd_t"), base);
  p.state_topic = expand(member(config, "mode_state_topic", "mode_stat_t"), base);
  auto modes = config.find("modes");
  // Home Assistant's default modes are auto, off, cool, heat, dry and fan_only.
  p.heat_mode = modes == config.end() ? "heat" : heat_mode_of(*modes);
  if (p.command_topic.empty()) p.heat_mode.clear();
  p.payload_on = p.heat_mode;
  p.payload_off = "off";
  p.min_c = number(config, "min_temp", nullptr, 7.0);
  p.max_c = number(config, "max_temp", nullptr, 35.0);
  if (p.min_c >= p.max_c) throw DiscoveryError("\"min_temp\" must be below \"max_temp\"");
}

}  // namespace

const char* type_name(DeviceType type) {
  switch (type) {
    case DeviceType::kLight:
      return "light";
    case DeviceType::kSwitch:
      return "switch";
    case DeviceType::kFan:
      return "fan";
    case DeviceType::kThermostat:
      return "thermostat";
  }
  return "light";
}

// (skills-builtin/home/heating.h says temperatures the same way on the skill's side of the
// Robot API.)
std::string celsius_text(double value) {
  const long tenths = std::lround(value * 10.0);
  std::string out = (tenths < 0 ? "-" : "") + std::to_string(std::labs(tenths) / 10);
  if (tenths % 10 != 0) out += "." + std::to_string(std::labs(tenths) % 10);
  return out;
}

std::string lower(std::string_view text) {
  std::string out(text);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  // Names are said, not typed: "_" and "-" read as spaces, and blanks collapse.
  std::string tidy;
  for (char c : out) {
    if (c == '_' || c == '-') c = ' ';
    if (c == ' ' && (tidy.empty() || tidy.back() == ' ')) continue;
    tidy += c;
  }
  while (!tidy.empty() && tidy.back() == ' ') tidy.pop_back();
  return tidy;
}

bool parse_ha_config_topic(std::string_view prefix, std::string_view topic, std::string* component,
                           std::string* object_id) {
  if (topic.size() <= prefix.size() + 1 || topic.substr(0, prefix.size()) != prefix ||
      topic[prefix.size()] != '/') {
    return false;
  }
  std::vector<std::string> parts;
  std::string_view rest = topic.substr(prefix.size() + 1);
  while (true) {
    std::size_t slash = rest.find('/');
    parts.emplace_back(rest.substr(0, slash));
    if (slash == std::string_view::npos) break;
    rest = rest.substr(slash + 1);
  }
  if (parts.size() < 3 || parts.size() > 4 || parts.back() != "config") return false;
  if (parts[0] != "light" && parts[0] != "switch" && parts[0] != "fan" && parts[0] != "climate")
    return false;
  *component = parts[0];
  *object_id = parts.size() == 4 ? parts[1] + "/" + parts[2] : parts[1];
  return true;
}

namespace {

// The config's name, else its device's, else the object id; `room` (lower case) from the
// device's suggested area.
std::string device_name(const json& config, std::string_view object_id, std::string* room) {
  std::string name = member(config, "name");
  for (const char* key : {"device", "dev"}) {
    auto it = config.find(key);
    if (it == config.end()) continue;
    if (!it->is_object()) throw DiscoveryError(std::string("\"") + key + "\" must be an object");
    if (name.empty()) name = member(*it, "name");
    *room = lower(member(*it, "suggested_area", "sa"));
  }
  return name.empty() ? std::string(object_id) : name;
}

}  // namespace

Device parse_ha_config(std::string_view component, std::string_view object_id,
                       std::string_view payload) {
  Device d;
  d.id = "ha:" + std::string(component) + "/" + std::string(object_id);
  if (payload.empty()) return d;  // the device was removed
  json config = parse(payload, "the discovery config");
  if (!config.is_object()) throw DiscoveryError("the discovery config must be a JSON object");
  d.type = component == "light"    ? DeviceType::kLight
           : component == "switch" ? DeviceType::kSwitch
           : component == "fan"    ? DeviceType::kFan
                                   : DeviceType::kThermostat;
  const std::string base = member(config, "~");
  DeviceProtocol& p = d.protocol;
  if (d.type != DeviceType::kThermostat) {
    p.command_topic = expand(member(config, "command_topic", "cmd_t"), base);
    if (p.command_topic.empty()) throw DiscoveryError("\"command_topic\" is missing");
    p.state_topic = expand(member(config, "state_topic", "stat_t"), base);
  }
  p.availability_topic = expand(member(config, "availability_topic", "avty_t"), base);
  if (p.availability_topic.empty()) {
    for (const char* key : {"availability", "avty"}) {
      auto it = config.find(key);
      if (it != config.end() && it->is_array() && !it->empty() && it->front().is_object()) {
        p.availability_topic = expand(member(it->front(), "topic", "t"), base);
      }
    }
  }
  if (std::string v = member(config, "payload_available", "pl_avail"); !v.empty())
    p.available_payload = v;
  if (std::string v = member(config, "payload_not_available", "pl_not_avail"); !v.empty())
    p.unavailable_payload = v;
  if (d.type == DeviceType::kThermostat) {
    read_ha_climate(config, base, &d);
    d.name = lower(device_name(config, object_id, &d.room));
    return d;
  }
  const bool json_schema = member(config, "schema") == "json";
  p.dialect = json_schema ? DeviceProtocol::Dialect::kHaJson : DeviceProtocol::Dialect::kHaDefault;
  if (std::string v = member(config, "payload_on", "pl_on"); !v.empty()) p.payload_on = v;
  if (std::string v = member(config, "payload_off", "pl_off"); !v.empty()) p.payload_off = v;
  p.state_on = p.payload_on;
  p.state_off = p.payload_off;
  if (std::string v = member(config, "state_on", "stat_on"); !v.empty()) p.state_on = v;
  if (std::string v = member(config, "state_off", "stat_off"); !v.empty()) p.state_off = v;
  for (const char* key : {"brightness_scale", "bri_scl"}) {
    auto it = config.find(key);
    if (it == config.end()) continue;
    if (!it->is_number_integer() || it->get<int>() <= 0) {
      throw DiscoveryError(std::string("\"") + key + "\" must be a positive integer");
    }
    p.brightness_max = it->get<int>();
  }
  if (json_schema) {
    auto it = config.find("brightness");
    if (it == config.end()) it = config.find("brightness");
    d.dimmable = it != config.end() && it->is_boolean() && it->get<bool>();
    auto modes = config.find("supported_color_modes");
    if (modes == config.end()) modes = config.find("sup_clrm");
    if (modes != config.end() && modes->is_array()) {
      for (const json& m : *modes) {
        if (m == "brightness" || m == "color_temp") d.dimmable = d.type == DeviceType::kLight;
        if (m == "color_temp") d.color_temp = true;
      }
    }
  } else {
    p.brightness_command_topic =
        expand(member(config, "brightness_command_topic", "bri_cmd_t"), base);
    p.brightness_state_topic = expand(member(config, "brightness_state_topic", "bri_stat_t"), base);
    d.dimmable = d.type == DeviceType::kLight && !p.brightness_command_topic.empty();
  }
  d.name = lower(device_name(config, object_id, &d.room));
  return d;
}

namespace {

// A Zigbee2MQTT "climate" expose: which property is the set point (and its range), and the
// system mode's values. No set point: `setpoint_property` stays empty.
void read_z2m_climate(const json& features, DeviceProtocol* p) {
  p->heat_mode.clear();
  for (const json& f : features) {
    if (!f.is_object()) continue;
    const std::string name = member(f, "name");
    if (name == "occupied_heating_setpoint" || name == "current_heating_setpoint") {
      // A valve that has both: the occupied set point is the one its schedule follows.
      if (p->setpoint_property == "occupied_heating_setpoint") continue;
      p->setpoint_property = name;
      // As for a light's brightness range: a range that is not one is left at the default,
      // so one odd device does not cost the whole list.
      auto bound = [&](const char* key, double fallback) {
        auto it = f.find(key);
        return it != f.end() && it->is_number() ? it->get<double>() : fallback;
      };
      p->min_c = bound("value_min", 5.0);
      p->max_c = bound("value_max", 30.0);
      if (p->min_c >= p->max_c) std::tie(p->min_c, p->max_c) = std::pair(5.0, 30.0);
    } else if (name == "system_mode") {
      auto values = f.find("values");
      if (values != f.end()) p->heat_mode = heat_mode_of(*values);
    }
  }
}

}  // namespace

std::vector<Device> parse_z2m_devices(std::string_view base_topic, std::string_view payload) {
  json list = parse(payload, "the device list");
  if (!list.is_array()) throw DiscoveryError("the device list must be a JSON array");
  std::vector<Device> out;
  for (std::size_t i = 0; i < list.size(); ++i) {
    const json& entry = list[i];
    const std::string where = "device [" + std::to_string(i) + "]";
    if (!entry.is_object()) throw DiscoveryError(where + " must be a JSON object");
    std::string friendly = member(entry, "friendly_name");
    if (friendly.empty()) throw DiscoveryError(where + " has no \"friendly_name\"");
    if (member(entry, "type") == "Coordinator") continue;
    auto definition = entry.find("definition");
    if (definition == entry.end() || !definition->is_object()) continue;  // not interviewed yet
    auto exposes = definition->find("exposes");
    if (exposes == definition->end() || !exposes->is_array()) continue;
    Device d;
    bool controllable = false;
    for (const json& e : *exposes) {
      if (!e.is_object()) continue;
      std::string type = member(e, "type");
      if (type != "light" && type != "switch" && type != "fan" && type != "climate") continue;
      controllable = true;
      d.type = type == "light"     ? DeviceType::kLight
               : type == "fan"     ? DeviceType::kFan
               : type == "climate" ? DeviceType::kThermostat
                                   : DeviceType::kSwitch;
      auto features = e.find("features");
      if (features == e.end() || !features->is_array()) continue;
      if (d.type == DeviceType::kThermostat) {
        read_z2m_climate(*features, &d.protocol);
        if (d.protocol.setpoint_property.empty()) controllable = false;  // nothing to set
        continue;
      }
      for (const json& f : *features) {
        if (!f.is_object()) continue;
        std::string name = member(f, "name");
        if (name == "brightness") {
          d.dimmable = true;
          auto max = f.find("value_max");
          if (max != f.end() && max->is_number_integer() && max->get<int>() > 0)
            d.protocol.brightness_max = max->get<int>();
          else
            d.protocol.brightness_max = 254;
        }
        if (name == "color_temp") d.color_temp = true;
      }
    }
    if (!controllable) continue;
    std::string name = friendly, room;
    if (std::size_t slash = friendly.rfind('/'); slash != std::string::npos) {
      room = friendly.substr(0, slash);
      name = friendly.substr(slash + 1);
    } else {
      std::string description = member(entry, "description");
      std::string l = lower(description);
      if (l.rfind("room:", 0) == 0) room = description.substr(5);
    }
    d.id = "z2m:" + friendly;
    d.name = lower(name);
    d.room = lower(room);
    const std::string topic = std::string(base_topic) + "/" + friendly;
    d.protocol.dialect = DeviceProtocol::Dialect::kZigbee2Mqtt;
    d.protocol.state_topic = topic;
    d.protocol.command_topic = topic + "/set";
    d.protocol.availability_topic = topic + "/availability";
    out.push_back(std::move(d));
  }
  return out;
}

bool apply_state(const Device& device, std::string_view topic, std::string_view payload,
                 DeviceState* state) {
  const DeviceProtocol& p = device.protocol;
  const bool thermostat = device.type == DeviceType::kThermostat;
  if (thermostat && p.dialect == DeviceProtocol::Dialect::kHaDefault) {
    std::optional<double> value;
    if (topic == p.state_topic && !p.state_topic.empty()) {
      if (payload.empty()) return false;
      state->on = payload != "off";  // heat, auto, cool...: the thermostat is working
    } else if (topic == p.setpoint_state_topic && !p.setpoint_state_topic.empty()) {
      if (!(value = celsius_of(payload))) return false;
      state->target_c = value;
    } else if (topic == p.current_temperature_topic && !p.current_temperature_topic.empty()) {
      if (!(value = celsius_of(payload))) return false;
      state->current_c = value;
    } else {
      return false;
    }
    ++state->reports;
    return true;
  }
  if (p.dialect == DeviceProtocol::Dialect::kHaDefault) {
    if (topic == p.state_topic) {
      std::optional<bool> on = on_of(std::string(payload), p.state_on, p.state_off);
      if (!on) return false;
      state->on = on;
    } else if (topic == p.brightness_state_topic && !p.brightness_state_topic.empty()) {
      char* end = nullptr;
      std::string text(payload);
      double raw = std::strtod(text.c_str(), &end);
      if (text.empty() || end != text.c_str() + text.size()) return false;
      state->brightness_pct = to_pct(raw, p.brightness_max);
    } else {
      return false;
    }
    ++state->reports;
    return true;
  }
  if (topic != p.state_topic) return false;
  json report;
  try {
    report = json::parse(payload);
  } catch (const json::parse_error&) {
    return false;
  }
  if (!report.is_object()) return false;
  bool any = false;
  if (auto it = report.find("state"); it != report.end() && it->is_string()) {
    if (std::optional<bool> on = on_of(it->get<std::string>(), "ON", "OFF")) {
      state->on = on;
      any = true;
    }
  }
  if (auto it = report.find("brightness"); it != report.end() && it->is_number()) {
    state->brightness_pct = to_pct(it->get<double>(), p.brightness_max);
    any = true;
  }
  if (auto it = report.find("color_temp"); it != report.end() && it->is_number_integer()) {
    state->color_temp = it->get<int>();
    any = true;
  }
  if (thermostat) {
    if (auto it = report.find(p.setpoint_property); it != report.end() && it->is_number()) {
      state->target_c = it->get<double>();
      any = true;
    }
    if (auto it = report.find("local_temperature"); it != report.end() && it->is_number()) {
      state->current_c = it->get<double>();
      any = true;
    }
    if (auto it = report.find("system_mode"); it != report.end() && it->is_string()) {
      state->on = it->get<std::string>() != "off";
      any = true;
    }
  }
  if (any) ++state->reports;
  return any;
}

bool apply_availability(const Device& device, std::string_view payload, DeviceState* state) {
  std::string text(payload);
  // Zigbee2MQTT sends {"state":"online"} (or plain "online" in older versions).
  if (!text.empty() && text.front() == '{') {
    try {
      json j = json::parse(text);
      if (j.is_object() && j.contains("state") && j["state"].is_string())
        text = j["state"].get<std::string>();
    } catch (const json::parse_error&) {
      return false;
    }
  }
  if (text == device.protocol.available_payload) {
    state->available = true;
  } else if (text == device.protocol.unavailable_payload) {
    state->available = false;
  } else {
    return false;
  }
  return true;
}

std::vector<std::pair<std::string, std::string>> command_messages(const Device& device,
                                                                  const DeviceCommand& command) {
  const DeviceProtocol& p = device.protocol;
  std::vector<std::pair<std::string, std::string>> out;
  const bool thermostat = device.type == DeviceType::kThermostat;
  if (thermostat) {
    // The mode first: a set point sent to a thermostat that is off may be dropped.
    const bool modes = !p.heat_mode.empty();
    const std::optional<double> target =
        command.target_c ? std::optional(std::clamp(*command.target_c, p.min_c, p.max_c))
                         : std::nullopt;
    if (p.dialect == DeviceProtocol::Dialect::kHaDefault) {
      if (command.on && modes) out.emplace_back(p.command_topic, *command.on ? p.heat_mode : "off");
      if (target) out.emplace_back(p.setpoint_command_topic, celsius_text(*target));
      return out;
    }
    json body = json::object();
    if (command.on && modes) body["system_mode"] = *command.on ? p.heat_mode : "off";
    if (target) body[p.setpoint_property] = static_cast<double>(std::lround(*target * 10.0)) / 10.0;
    if (!body.empty()) out.emplace_back(p.command_topic, body.dump());
    return out;
  }
  if (p.dialect == DeviceProtocol::Dialect::kHaDefault) {
    if (command.on) out.emplace_back(p.command_topic, *command.on ? p.payload_on : p.payload_off);
    if (command.brightness_pct && !p.brightness_command_topic.empty()) {
      out.emplace_back(p.brightness_command_topic,
                       std::to_string(from_pct(*command.brightness_pct, p.brightness_max)));
    }
    return out;
  }
  json body = json::object();
  if (command.on) body["state"] = *command.on ? "ON" : "OFF";
  if (command.brightness_pct && device.dimmable) {
    body["brightness"] = from_pct(*command.brightness_pct, p.brightness_max);
  }
  if (command.color_temp && device.color_temp) body["color_temp"] = *command.color_temp;
  if (!body.empty()) out.emplace_back(p.command_topic, body.dump());
  return out;
}

bool state_matches(const DeviceState& state, const DeviceCommand& command) {
  if (command.on && state.on != command.on) return false;
  if (command.brightness_pct && state.brightness_pct &&
      std::abs(*state.brightness_pct - *command.brightness_pct) > 1) {
    return false;
  }
  if (command.brightness_pct && !state.brightness_pct && !command.on) return false;
  if (command.color_temp && state.color_temp != command.color_temp) return false;
  // Thermostats keep their set point in steps (0.5 or 1 degree): 21.3 asked is 21.5 or 21
  // reported, and that is the command carried out.
  if (command.target_c && (!state.target_c || std::abs(*state.target_c - *command.target_c) > 0.5))
    return false;
  return true;
}

}  // namespace marvin::home
