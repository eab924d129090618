// Which device(s) a spoken phrase means: "the bedroom light", "the fan", "the living room
// lights", "the big lamp". Pure (devices JSON in, indices out), so it is tested alone.
//
//   1. A device's exact name or alias wins ("the big lamp").
//   2. Otherwise a room named in the phrase narrows to that room, and the remaining words
//      must all fit the device: words of its name, or its kind ("light", "lamp", "fan",
//      "switch", "tv"; "lamp" only names lamps when some device is named one); "lights"
//      and the like are plural.
//   3. Without a room in the phrase, devices in the room the robot is in are preferred.
//   4. Several left: all of them when the phrase was plural, else ambiguous (the skill asks).
// "all", "every", "both" or the whole home ("in the house", "everywhere") make the phrase
// plural and skip 3: "turn off all the lights" means every light, not the ones in this room.
#pragma once

#include <algorithm>
#include <cctype>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <vector>

namespace marvin_home_skill {

inline std::vector<std::string> words(const std::string& text) {
  std::vector<std::string> out;
  std::string w;
  for (char c : text + " ") {
    if (std::isalnum(static_cast<unsigned char>(c)) || c == '\'') {
      w += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    } else if (!w.empty()) {
      out.push_back(w);
      w.clear();
    }
  }
  return out;
}

inline std::string join(const std::vector<std::string>& ws) {
  std::string out;
  for (const std::string& w : ws) out += (out.empty() ? "" : " ") + w;
  return out;
}

// "the big lamp" -> "big lamp": articles and possessives say nothing about the device.
inline std::string tidy(const std::string& text) {
  // "turn the heating down a bit": how much is no word of a device's name ("a little" is
  // left to resolve's describing words: a device may be called "little lamp").
  static const std::set<std::string> skip = {"the",  "a",    "my",  "our",    "your",
                                             "this", "that", "one", "please", "bit",
                                             "slightly", "notch"};
  std::vector<std::string> out;
  for (const std::string& w : words(text)) {
    if (!skip.count(w)) out.push_back(w);
  }
  return join(out);
}

struct Resolution {
  std::vector<std::size_t> matches;  // indices into the devices array
  bool plural = false;               // "lights": every match is meant
  bool everywhere = false;           // "all the lights", "the lights in the house"
  std::string room;                  // the room named in the phrase, if any
};

// Words that widen a phrase to every device that fits, in every room.
inline bool everywhere_word(const std::string& w) {
  static const std::set<std::string> kWords = {"all",        "every", "each",  "both",
                                               "everywhere", "house", "home",  "whole",
                                               "apartment",  "flat",  "entire"};
  return kWords.count(w) > 0;
}

inline bool kind_word(const std::string& w, const std::string& type, bool* plural) {
  static const std::vector<std::pair<std::string, std::string>> kinds = {
      {"light", "light"},   {"lamp", "light"},    {"bulb", "light"},
      {"fan", "fan"},       {"switch", "switch"}, {"plug", "switch"},
      {"socket", "switch"}, {"device", "*"},      {"thing", "*"},
      {"thermostat", "thermostat"}, {"heating", "thermostat"}, {"heater", "thermostat"},
      {"radiator", "thermostat"},   {"heat", "thermostat"},    {"temperature", "thermostat"}};
  for (const auto& [word, kind] : kinds) {
    if (w == word || w == word + "s" || w == word + "es") {
      if (w != word) *plural = true;
      // "all the devices" leaves the heating alone: it is switched off only when named.
      return kind == "*" ? type != "thermostat" : kind == type;
    }
  }
  return false;
}

// `devices`: the "devices" array of smarthome_devices(); `here`: the robot's room.
inline Resolution resolve(const nlohmann::json& devices, const std::string& phrase,
                          const std::string& here) {
  Resolution r;
  const std::string said = tidy(phrase);
  // 1. Exact name or alias.
  for (std::size_t i = 0; i < devices.size(); ++i) {
    const nlohmann::json& d = devices[i];
    bool exact = tidy(d.value("name", "")) == said;
    for (const auto& a : d.value("aliases", nlohmann::json::array())) {
      if (a.is_string() && tidy(a.get<std::string>()) == said) exact = true;
    }
    if (exact) r.matches.push_back(i);
  }
  if (!r.matches.empty()) return r;
  // 2. A room in the phrase (the longest one named), and the words left.
  std::vector<std::string> rest = words(said);
  std::set<std::string> rooms;
  for (const auto& d : devices) rooms.insert(d.value("room", ""));
  std::size_t best = 0;
  for (const std::string& room : rooms) {
    std::vector<std::string> rw = words(room);
    if (rw.empty() || rw.size() <= best) continue;
    auto at = std::search(rest.begin(), rest.end(), rw.begin(), rw.end());
    if (at != rest.end()) {
      r.room = room;
      best = rw.size();
    }
  }
  if (!r.room.empty()) {
    std::vector<std::string> rw = words(r.room);
    auto at = std::search(rest.begin(), rest.end(), rw.begin(), rw.end());
    rest.erase(at, at + static_cast<std::ptrdiff_t>(rw.size()));
  }
  rest.erase(std::remove_if(rest.begin(), rest.end(),
                            [&](const std::string& w) {
                              if (everywhere_word(w)) r.everywhere = r.plural = true;
                              // "is the heating on in the bedroom": the state asked
                              // about is no word of the device's name.
                              return w == "in" || w == "of" || w == "on" || w == "off" ||
                                     everywhere_word(w);
                            }),
             rest.end());
  // "The big light", "the main light": words that describe a light without naming it, when
  // no device's name has them, leave the kind ("light") and the room to decide.
  static const std::set<std::string> kDescribing = {"big",      "main", "ceiling", "overhead",
                                                    "top",      "little", "small", "usual"};
  rest.erase(std::remove_if(rest.begin(), rest.end(),
                            [&](const std::string& w) {
                              if (!kDescribing.count(w)) return false;
                              for (const auto& d : devices) {
                                const std::vector<std::string> n = words(d.value("name", ""));
                                if (std::find(n.begin(), n.end(), w) != n.end()) return false;
                              }
                              return true;
                            }),
             rest.end());
  // "The lamp" is the living room lamp, not any light, when a device is named a lamp; a
  // kind word that names a shape ("lamp", "plug", "radiator"), unlike "light", is then
  // only a word of names.
  static const std::set<std::string> kShapes = {"lamp", "bulb", "plug", "socket", "radiator",
                                                "heater"};
  auto named_somewhere = [&](std::string w) {
    if (w.size() > 1 && w.back() == 's' && !kShapes.count(w)) w.pop_back();
    if (!kShapes.count(w)) return false;
    for (const auto& d : devices) {
      const std::vector<std::string> n = words(d.value("name", ""));
      if (std::find(n.begin(), n.end(), w) != n.end()) return true;
    }
    return false;
  };
  for (std::size_t i = 0; i < devices.size(); ++i) {
    const nlohmann::json& d = devices[i];
    if (!r.room.empty() && d.value("room", "") != r.room) continue;
    std::vector<std::string> name = words(d.value("name", ""));
    const std::string type = d.value("type", "light");
    bool fits = true;
    for (const std::string& w : rest) {
      bool plural = false;
      bool in_name = std::find(name.begin(), name.end(), w) != name.end();
      if (!in_name && w.size() > 1 && w.back() == 's') {
        const std::string singular = w.substr(0, w.size() - 1);
        in_name = std::find(name.begin(), name.end(), singular) != name.end();
        if (in_name) r.plural = true;
      }
      if (!in_name && (named_somewhere(w) || !kind_word(w, type, &plural))) fits = false;
      if (plural) r.plural = true;
    }
    if (fits) r.matches.push_back(i);
  }
  // 3. Several, no room said: the room the robot is in first.
  if (r.room.empty() && !r.everywhere && r.matches.size() > 1 && !here.empty()) {
    std::vector<std::size_t> local;
    for (std::size_t i : r.matches) {
      if (devices[i].value("room", "") == here) local.push_back(i);
    }
    if (!local.empty()) r.matches = local;
  }
  return r;
}

// "the hall light, the kitchen light or the bedroom light"
inline std::string choices(const nlohmann::json& devices, const std::vector<std::size_t>& which) {
  std::string out;
  for (std::size_t k = 0; k < which.size(); ++k) {
    if (k > 0) out += k + 1 == which.size() ? " or " : ", ";
    out += "the " + devices[which[k]].value("name", "");
  }
  return out;
}

}  // namespace marvin_home_skill
