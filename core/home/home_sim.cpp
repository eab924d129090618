#include "home/home_sim.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>

namespace marvin::home {
namespace {
using nlohmann::json;
}

std::vector<SimDevice> load_world_devices(const std::filesystem::path& world) {
  const std::string file = world.string();
  std::ifstream in(world);
  if (!in) throw std::runtime_error("cannot read the world file " + file);
  std::stringstream text;
  text << in.rdbuf();
  json doc;
  try {
    doc = json::parse(text.str());
  } catch (const json::parse_error& e) {
    throw std::runtime_error(file + ": not valid JSON at byte " + std::to_string(e.byte));
  }
  if (!doc.is_object() || !doc.contains("devices") || !doc["devices"].is_array()) {
    throw std::runtime_error(file + ": $.devices must be an array of devices");
  }
  std::vector<SimDevice> out;
  const json& list = doc["devices"];
  for (std::size_t i = 0; i < list.size(); ++i) {
    const std::string path = file + ": $.devices[" + std::to_string(i) + "]";
    const json& d = list[i];
    if (!d.is_object()) throw std::runtime_error(path + " must be an object");
    SimDevice s;
    for (auto [key, target] : {std::pair{"name", &s.name}, {"type", &s.type}, {"room", &s.room}}) {
      if (!d.contains(key) || !d[key].is_string() || d[key].get<std::string>().empty()) {
        throw std::runtime_error(path + "." + key + " must be a non-empty string");
      }
      *target = d[key].get<std::string>();
    }
    if (s.type != "light" && s.type != "switch" && s.type != "fan" && s.type != "thermostat") {
      throw std::runtime_error(path + ".type must be light, switch, fan or thermostat, got \"" +
                               s.type + "\"");
    }
    if (d.contains("temperature")) {
      if (!d["temperature"].is_number() || s.type != "thermostat")
        throw std::runtime_error(path + ".temperature must be a number, on a thermostat");
      s.temperature = d["temperature"].get<double>();
    }
    s.on = s.type == "thermostat";  // heating, at its set point
    if (d.contains("dimmable")) {
      if (!d["dimmable"].is_boolean())
        throw std::runtime_error(path + ".dimmable must be true or false");
      s.dimmable = d["dimmable"].get<bool>();
    }
    out.push_back(std::move(s));
  }
  return out;
}

HomeSimulator::HomeSimulator(std::vector<SimDevice> devices, std::string base,
                             std::set<std::string> mute)
    : devices_(std::move(devices)), base_(std::move(base)), mute_(std::move(mute)) {}

std::string HomeSimulator::state_json(const SimDevice& d) const {
  if (d.type == "thermostat") {
    return json{{"occupied_heating_setpoint", d.setpoint},
                {"local_temperature", d.temperature},
                {"system_mode", d.on ? "heat" : "off"},
                {"linkquality", 120}}
        .dump();
  }
  json state{{"state", d.on ? "ON" : "OFF"}, {"linkquality", 120}};
  if (d.dimmable) {
    state["brightness"] = d.brightness;
    state["color_temp"] = d.color_temp;
  }
  return state.dump();
}

std::string HomeSimulator::devices_json() const {
  json list = json::array();
  list.push_back({{"friendly_name", "Coordinator"},
                  {"ieee_address", "0x00124b0000000000"},
                  {"type", "Coordinator"}});
  int n = 1;
  for (const SimDevice& d : devices_) {
    json features = json::array({{{"name", "state"},
                                  {"property", "state"},
                                  {"type", "binary"},
                                  {"value_on", "ON"},
                                  {"value_off", "OFF"}}});
    if (d.dimmable) {
      features.push_back({{"name", "brightness"},
                          {"property", "brightness"},
                          {"type", "numeric"},
                          {"value_min", 0},
                          {"value_max", 254}});
      features.push_back({{"name", "color_temp"},
                          {"property", "color_temp"},
                          {"type", "numeric"},
                          {"value_min", 150},
                          {"value_max", 500}});
    }
    if (d.type == "thermostat") {
      features = json::array({{{"name", "occupied_heating_setpoint"},
                               {"property", "occupied_heating_setpoint"},
                               {"type", "numeric"},
                               {"unit", "°C"},
                               {"value_min", 5},
                               {"value_max", 30},
                               {"value_step", 0.5}},
                              {{"name", "local_temperature"},
                               {"property", "local_temperature"},
                               {"type", "numeric"},
                               {"unit", "°C"}},
                              {{"name", "system_mode"},
                               {"property", "system_mode"},
                               {"type", "enum"},
                               {"values", {"off", "heat"}}}});
    }
    const std::string expose = d.type == "thermostat" ? "climate" : d.type;
    char ieee[32];
    std::snprintf(ieee, sizeof ieee, "0x00158d00%08x", n++);
    list.push_back({{"friendly_name", friendly_name(d)},
                    {"ieee_address", ieee},
                    {"type", "Router"},
                    {"supported", true},
                    {"description", "room: " + d.room},
                    {"definition",
                     {{"model", "SIM-" + d.type},
                      {"vendor", "Marvin"},
                      {"description", "simulated " + d.type},
                      {"exposes", json::array({{{"type", expose}, {"features", features}}})}}}});
  }
  return list.dump();
}

std::vector<std::pair<std::string, std::string>> HomeSimulator::announce() const {
  std::vector<std::pair<std::string, std::string>> out;
  out.emplace_back(base_ + "/bridge/state", R"({"state":"online"})");
  out.emplace_back(base_ + "/bridge/devices", devices_json());
  for (const SimDevice& d : devices_) {
    out.emplace_back(base_ + "/" + friendly_name(d) + "/availability", R"({"state":"online"})");
    out.emplace_back(base_ + "/" + friendly_name(d), state_json(d));
  }
  return out;
}

std::vector<std::pair<std::string, std::string>> HomeSimulator::handle(
    const std::string& topic, std::string_view payload, std::vector<std::string>* lines) {
  std::vector<std::pair<std::string, std::string>> out;
  for (SimDevice& d : devices_) {
    const std::string t = base_ + "/" + friendly_name(d);
    const bool is_set = topic == t + "/set";
    if (!is_set && topic != t + "/get") continue;
    if (mute_.count(d.name)) return out;
    if (is_set) {
      json command;
      try {
        command = json::parse(payload);
      } catch (const json::parse_error&) {
        lines->push_back(d.name + ": ignored a command that is not JSON");
        return out;
      }
      if (!command.is_object()) return out;
      if (d.type == "thermostat") {
        if (auto it = command.find("occupied_heating_setpoint"); it != command.end() && it->is_number())
          d.setpoint = std::clamp(std::round(it->get<double>() * 2.0) / 2.0, 5.0, 30.0);
        if (auto it = command.find("system_mode"); it != command.end() && it->is_string())
          d.on = it->get<std::string>() != "off";
        std::ostringstream line;
        line << d.name << ": " << (d.on ? "heat " : "off ") << d.setpoint;
        lines->push_back(line.str());
        out.emplace_back(t, state_json(d));
        return out;
      }
      if (auto it = command.find("state"); it != command.end() && it->is_string()) {
        std::string s = it->get<std::string>();
        std::transform(s.begin(), s.end(), s.begin(), ::toupper);
        if (s == "ON") d.on = true;
        if (s == "OFF") d.on = false;
        if (s == "TOGGLE") d.on = !d.on;
      }
      if (d.dimmable) {
        if (auto it = command.find("brightness"); it != command.end() && it->is_number()) {
          d.brightness = std::clamp(it->get<int>(), 0, 254);
          d.on = d.brightness > 0;
        }
        if (auto it = command.find("color_temp"); it != command.end() && it->is_number()) {
          d.color_temp = std::clamp(it->get<int>(), 150, 500);
        }
      }
      lines->push_back(d.name + ": " + (d.on ? "ON" : "OFF") +
                       (d.dimmable ? " " + std::to_string(d.brightness) : std::string()));
    }
    out.emplace_back(t, state_json(d));
    return out;
  }
  return out;
}

}  // namespace marvin::home
