#include "home/discovery.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>

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

int clamp_pct(double value) {
  return static_cast<int>(std::clamp(std::lround(value), 0L, 100L));
}

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

}  // namespace

const char* type_name(DeviceType type) {
  switch (type) {
    case DeviceType::kLight:
      return "light";
    case DeviceType::kSwitch:
      return "switch";
    case DeviceType::kFan:
      return "fan";
  }
  return "light";
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

bool parse_ha_config_topic(std::string_view prefix, std::string_view topic,
                           std::string* component, std::string* object_id) {
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
  if (parts[0] != "light" && parts[0] != "switch" && parts[0] != "fan") return false;
  *component = parts[0];
  *object_id = parts.size() == 4 ? parts[1] + "/" + parts[2] : parts[1];
  return true;
}

Device parse_ha_config(std::string_view component, std::string_view object_id,
                       std::string_view payload) {
  Device d;
  d.id = "ha:" + std::string(component) + "/" + std::string(object_id);
  if (payload.empty()) return d;  // the device was removed
  json config = parse(payload, "the discovery config");
  if (!config.is_object()) throw DiscoveryError("the discovery config must be a JSON object");
  d.type = component == "light"    ? DeviceType::kLight
           : component == "switch" ? DeviceType::kSwitch
                                   : DeviceType::kFan;
  const std::string base = member(config, "~");
  DeviceProtocol& p = d.protocol;
  p.command_topic = expand(member(config, "command_topic", "cmd_t"), base);
  if (p.command_topic.empty()) throw DiscoveryError("\"command_topic\" is missing");
  p.state_topic = expand(member(config, "state_topic", "stat_t"), base);
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
  std::string name = member(config, "name");
  std::string room;
  for (const char* key : {"device", "dev"}) {
    auto it = config.find(key);
    if (it == config.end()) continue;
    if (!it->is_object()) throw DiscoveryError(std::string("\"") + key + "\" must be an object");
    if (name.empty()) name = member(*it, "name");
    room = member(*it, "suggested_area", "sa");
  }
  if (name.empty()) name = std::string(object_id);
  d.name = lower(name);
  d.room = lower(room);
  return d;
}

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
      if (type != "light" && type != "switch" && type != "fan") continue;
      controllable = true;
      d.type = type == "light" ? DeviceType::kLight
               : type == "fan" ? DeviceType::kFan
                               : DeviceType::kSwitch;
      auto features = e.find("features");
      if (features == e.end() || !features->is_array()) continue;
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
  return true;
}

}  // namespace marvin::home
