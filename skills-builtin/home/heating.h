// Thermostats in words: whether a request is about the heating, and what a thermostat's
// reported state sounds like. Pure (JSON of smarthome_devices in, sentences out), so it is
// tested alone.
#pragma once

#include <cmath>
#include <nlohmann/json.hpp>
#include <set>
#include <string>

#include "resolve.h"

namespace marvin_home_skill {

// "I'm cold" turns the set point up by this much; a degree is what a person notices.
inline constexpr double kWarmthStep = 1.0;

// "turn up the heating", "set it to 21 degrees", "how warm is it": the request is about
// warmth, not light, whichever intent its sentence shape reached.
inline bool about_heating(const std::string& utterance) {
  static const std::set<std::string> kWords = {
      "temperature", "degrees", "degree", "heating", "heat",  "heater", "heaters",
      "thermostat",  "thermostats", "radiator", "radiators", "warm", "warmer",
      "cold",        "colder",  "cool",    "cooler", "hot",   "hotter", "chilly", "freezing"};
  for (const std::string& w : words(utterance)) {
    if (kWords.count(w)) return true;
  }
  return false;
}

// 21 -> "21", 19.5 -> "19.5": as a person says it.
inline std::string degrees(double celsius) {
  const long tenths = std::lround(celsius * 10.0);
  std::string out = (tenths < 0 ? "-" : "") + std::to_string(std::labs(tenths) / 10);
  if (tenths % 10 != 0) out += "." + std::to_string(std::labs(tenths) % 10);
  return out;
}

// "here", "in here", "this room" (tidied): the room the robot is in, not one named.
inline bool means_this_room(const std::string& said) {
  return said == "here" || said == "in here" || said == "this room";
}

inline bool is_thermostat(const nlohmann::json& device) {
  return device.value("type", "") == "thermostat";
}

// "the living room thermostat is on, set to 21 degrees" / "... is off" (lower case, no
// full stop: it is joined with others).
inline std::string thermostat_state(const nlohmann::json& d) {
  std::string out = "the " + d.value("name", "");
  const nlohmann::json on = d.value("on", nlohmann::json());
  const nlohmann::json target = d.value("target_temperature", nlohmann::json());
  if (on.is_boolean() && !on.get<bool>()) return out + " is off";
  if (!target.is_number()) return out + " hasn't told me its setting";
  return out + (on.is_boolean() ? " is on, set to " : " is set to ") +
         degrees(target.get<double>()) + " degrees";
}

// "It's 19.5 degrees in the living room." (or "The bedroom thermostat measures 18 degrees."
// for a thermostat without a room); "" when it has not reported a temperature.
inline std::string room_temperature(const nlohmann::json& d) {
  const nlohmann::json t = d.value("temperature", nlohmann::json());
  if (!t.is_number()) return "";
  const std::string room = d.value("room", "");
  if (room.empty()) {
    return "The " + d.value("name", "") + " measures " + degrees(t.get<double>()) + " degrees.";
  }
  return "It's " + degrees(t.get<double>()) + " degrees in the " + room + ".";
}

}  // namespace marvin_home_skill
