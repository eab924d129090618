// Built-in skill "home": lights, fans, switches and the heating by voice, through the Robot
// API's smarthome_devices and smarthome_set (API 1.2; thermostats since 1.6).
//   "turn on the bedroom light"            "switch off the fan"
//   "dim the living room lights to 30 percent"   "make it brighter"
//   "is the kitchen light on?"             "turn everything off in the bedroom"
//   "turn off all the lights" (every room) "turn everything off in the house"
//   "I'm cold" / "make it cooler in the bedroom" (the set point a degree up or down)
//   "set the heating to 21 degrees"        "what's the temperature in here?"
// "Everything off" leaves thermostats alone: a person who is cold at night must not find
// the heating switched off by a sentence about the lights; "turn off the heating" does it.
// "Dim the lights" or "brighter" with several lights in reach changes the ones that are on,
// and only lights: a dark room stays dark, the tv stays off.
// The device comes from the room named (or the room the robot is in) and the name; when
// that leaves several, the skill asks ("The hall light or the bedroom light?"). Every
// "it's on" is said after the device itself reported it (smarthome_set returns then);
// otherwise the skill says the device did not answer, or that the home's hub is not
// reachable (the host keeps reconnecting meanwhile).
#include <algorithm>
#include <cctype>
#include <marvin/skill.hpp>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "common/spoken_text.h"
#include "heating.h"
#include "resolve.h"

namespace {

using marvin::builtin::capital;

using marvin_home_skill::about_heating;
using marvin_home_skill::degrees;
using marvin_home_skill::is_thermostat;
using marvin_home_skill::Resolution;
using nlohmann::json;

constexpr int kStep = 25;  // "brighter": a quarter of the range

// "what's the temperature in the living room", "how warm is the fridge set".
bool asks_temperature(const std::string& utterance) {
  std::string word;
  for (char c : utterance + " ") {
    if (std::isalpha(static_cast<unsigned char>(c))) {
      word += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
      continue;
    }
    for (const char* w : {"temperature", "warm", "warmer", "cold", "colder", "hot", "degrees"}) {
      if (word == w) return true;
    }
    word.clear();
  }
  return false;
}

class HomeSkill : public marvin::Skill {
 public:
  using marvin::Skill::Skill;

  void handle(const marvin::Request& request) override {
    std::optional<json> home = load();
    if (!home) return;
    const std::string& intent = request.intent;
    auto text = [&](const char* slot) {
      auto it = request.slots.find(slot);
      return it != request.slots.end() && it->is_string() ? it->get<std::string>() : std::string();
    };
    if (intent == "turn_on" || intent == "turn_off") {
      return switch_devices(*home, text("device"), intent == "turn_on");
    }
    // The sentence shapes of light and heat are alike ("turn up the heating", "set the
    // heating to 21"): the words about warmth decide.
    const bool heating =
        about_heating(request.utterance) || !last_thermostats(*home, text("device")).empty();
    if (intent == "set_level") {
      int level = request.slots.value("level", -1);
      if (heating || room_set_point(*home, text("device"), level)) {
        return set_temperature(*home, text("device"), level);
      }
      return set_level(*home, text("device"), level);
    }
    if (intent == "warmer" || intent == "cooler") {
      return change_warmth(*home, text("room"), intent == "warmer");
    }
    if (intent == "brighter" || intent == "dimmer") {
      if (heating) return change_warmth(*home, text("device"), intent == "brighter");
      std::string device = text("device");
      // "It's too dark in here": the lights of the robot's room, not the last ones switched.
      const std::vector<std::string> w = marvin_home_skill::words(request.utterance);
      if (device.empty() && std::find(w.begin(), w.end(), "here") != w.end() &&
          !home->value("room", "").empty()) {
        device = "lights in the " + home->value("room", "");
      }
      return step(*home, device, intent == "brighter" ? kStep : -kStep);
    }
    if (intent == "temperature") return temperature(*home, text("room"));
    if (intent == "query") {
      // "is the heating on in the bedroom": the room said after the state.
      std::string device = text("device");
      if (!text("room").empty()) device += " in the " + text("room");
      if (asks_temperature(request.utterance)) return temperature(*home, device);
      return query(*home, device, yes_no_question(request.utterance));
    }
    if (intent == "all_off") return all_off(*home, text("room"));
    if (intent == "what_is_on") {
      const std::vector<std::string> w = marvin_home_skill::words(request.utterance);
      const bool all_off = std::find(w.begin(), w.end(), "off") != w.end();
      return what_is_on(*home, text("room"), all_off, yes_no_question(request.utterance));
    }
  }

 private:
  // The devices, or nullopt after telling the user why there are none.
  std::optional<json> load() {
    json home;
    try {
      home = robot().smarthome_devices();
    } catch (const marvin::Error& e) {
      if (e.status() != MARVIN_ERR_UNAVAILABLE) throw;
      robot().say("I'm not connected to a smart home.");
      return std::nullopt;
    }
    if (!home.value("connected", false) && home["devices"].empty()) {
      robot().say("I can't reach the home's hub right now. I'll keep trying.");
      return std::nullopt;
    }
    return home;
  }

  // The devices `phrase` means; asks when it is ambiguous. Empty after telling the user.
  std::vector<json> pick(const json& home, std::string phrase, bool allow_many = false) {
    const json& devices = home["devices"];
    const std::string here = home.value("room", "");
    if (marvin_home_skill::tidy(phrase).empty() || phrase == "it" || phrase == "them") {
      if (last_ && !last_->empty()) {
        std::vector<json> out;
        for (const std::string& id : *last_) {
          for (const json& d : devices) {
            if (d["id"] == id) out.push_back(d);
          }
        }
        if (!out.empty()) return out;
      }
      phrase = "light";
    }
    Resolution r = marvin_home_skill::resolve(devices, phrase, here);
    if (r.matches.empty()) {
      // "the kitchen light and the hall light": each, unless one of them is unknown.
      const std::vector<std::string> parts = split_on_and(phrase);
      if (parts.size() > 1) {
        std::vector<json> out;
        for (const std::string& part : parts) {
          const std::vector<json> some = pick(home, part, allow_many);
          if (some.empty()) return {};  // told the user which one; nothing is switched
          for (const json& d : some) {
            if (std::find(out.begin(), out.end(), d) == out.end()) out.push_back(d);
          }
        }
        return out;
      }
      robot().say("I don't know a device called the " + marvin_home_skill::tidy(phrase) + ".");
      return {};
    }
    if (r.matches.size() > 1 && !(r.plural || allow_many)) {
      std::vector<std::size_t> shown = r.matches;
      const std::string question = capital(marvin_home_skill::choices(devices, shown)) + "?";
      std::string answer = robot().ask(question);
      Resolution a = marvin_home_skill::resolve(devices, answer, "");
      std::vector<std::size_t> both;
      for (std::size_t i : a.matches) {
        if (std::find(shown.begin(), shown.end(), i) != shown.end()) both.push_back(i);
      }
      if (both.size() != 1) both = in_room_named(devices, shown, answer);
      if (both.size() != 1) {
        robot().say("Sorry, I still don't know which one you mean.");
        return {};
      }
      r.matches = both;
    }
    std::vector<json> out;
    for (std::size_t i : r.matches) out.push_back(devices[i]);
    return out;
  }

  // "the tv and the lamp" -> {"the tv", "the lamp"}; a phrase without "and" -> {phrase}.
  static std::vector<std::string> split_on_and(const std::string& phrase) {
    std::vector<std::string> parts(1);
    for (const std::string& w : marvin_home_skill::words(phrase)) {
      if (w == "and") {
        parts.emplace_back();
      } else {
        parts.back() += (parts.back().empty() ? "" : " ") + w;
      }
    }
    if (std::any_of(parts.begin(), parts.end(), [](const std::string& p) { return p.empty(); })) {
      return {phrase};
    }
    return parts;
  }

  // Of the devices `shown`, those whose room `answer` names ("the one in the bedroom",
  // "make it warmer in the living room").
  static std::vector<std::size_t> in_room_named(const json& devices,
                                                const std::vector<std::size_t>& shown,
                                                const std::string& answer) {
    const std::string said = " " + marvin_home_skill::join(marvin_home_skill::words(answer)) + " ";
    std::vector<std::size_t> out;
    for (std::size_t i : shown) {
      const std::string room = devices[i].value("room", "");
      if (!room.empty() && said.find(" " + room + " ") != std::string::npos) out.push_back(i);
    }
    return out;
  }

  // Sends `state` to `device`; the device's reported state afterwards, or nullopt after
  // saying what went wrong.
  std::optional<json> command(const json& device, const json& state) {
    const std::string name = device.value("name", "");
    try {
      robot().smarthome_set(device.value("id", name), state);
    } catch (const marvin::Error& e) {
      if (e.status() != MARVIN_ERR_UNAVAILABLE) throw;
      json home = robot().smarthome_devices();
      if (!home.value("connected", false)) {
        robot().say("I can't reach the home's hub right now, so the " + name +
                    " is unchanged. I'll keep trying to reconnect.");
      } else if (!reported(home, device).value("available", true)) {
        robot().say("The " + name + " is offline.");
      } else {
        robot().say("The " + name + " didn't answer.");
      }
      return std::nullopt;
    }
    return reported(robot().smarthome_devices(), device);
  }

  static json reported(const json& home, const json& device) {
    for (const json& d : home["devices"]) {
      if (d["id"] == device["id"]) return d;
    }
    return device;
  }

  static std::string describe(const json& d) {
    if (is_thermostat(d)) return marvin_home_skill::thermostat_state(d);
    std::string out = "the " + d.value("name", "");
    const json on = d.value("on", json());
    if (!on.is_boolean()) return out + " hasn't told me its state";
    out += on.get<bool>() ? " is on" : " is off";
    const json b = d.value("brightness", json());
    if (on.get<bool>() && d.value("dimmable", false) && b.is_number_integer() &&
        b.get<int>() < 100) {
      out += ", at " + std::to_string(b.get<int>()) + " percent";
    }
    return out;
  }

  void remember(const std::vector<json>& devices) {
    std::vector<std::string> ids;
    for (const json& d : devices) ids.push_back(d.value("id", ""));
    last_ = ids;
  }

  void report(const std::vector<json>& done) {
    if (!done.empty()) robot().say(capital(states(done)) + ".");
  }

  // "the hall light, the kitchen light and the bedroom light are off": several now alike
  // each named once with the state once; else each with its own state.
  static std::string states(const std::vector<json>& done) {
    const json first_on = done[0].value("on", json());
    const bool alike = done.size() > 1 && first_on.is_boolean() &&
                       std::all_of(done.begin(), done.end(), [&](const json& d) {
                         return d.value("on", json()) == first_on &&
                                describe(d) == "the " + d.value("name", "") +
                                                   (first_on.get<bool>() ? " is on" : " is off");
                       });
    std::string text;
    for (std::size_t i = 0; i < done.size(); ++i) {
      if (i > 0) text += i + 1 == done.size() ? " and " : ", ";
      text += alike ? "the " + done[i].value("name", "") : describe(done[i]);
    }
    if (alike) text += first_on.get<bool>() ? " are on" : " are off";
    return text;
  }

  void switch_devices(const json& home, const std::string& phrase, bool on) {
    std::vector<json> devices = pick(home, phrase);
    remember(devices);
    std::vector<json> done;
    for (const json& d : devices) {
      if (is_thermostat(d) && !d.value("switchable", true)) {
        robot().say("The " + d.value("name", "") +
                    " can't be switched on or off, only set to a temperature.");
        continue;
      }
      if (auto state = command(d, json{{"on", on}})) done.push_back(*state);
    }
    report(done);
  }

  void set_level(const json& home, const std::string& phrase, int level) {
    if (level < 0 || level > 100) {
      robot().say("I can set a light from 0 to 100 percent.");
      return;
    }
    // "set the living room to 50 percent": a level is for what dims, so the lamp, not the
    // thermostat or the tv; the whole home only when nothing that dims fits the words.
    std::vector<json> devices;
    const std::string said = marvin_home_skill::tidy(phrase);
    if (!said.empty() && said != "it" && said != "them") {
      json dimmable = home;
      dimmable["devices"] = json::array();
      for (const json& d : home["devices"]) {
        if (d.value("dimmable", false)) dimmable["devices"].push_back(d);
      }
      if (!marvin_home_skill::resolve(dimmable["devices"], phrase, home.value("room", ""))
               .matches.empty()) {
        devices = pick(dimmable, phrase);
      }
    }
    if (devices.empty()) devices = pick(home, phrase);
    devices = lit_ones(std::move(devices));
    remember(devices);
    std::vector<json> done;
    for (const json& d : devices) {
      if (!d.value("dimmable", false)) {
        robot().say("The " + d.value("name", "") + " can't be dimmed.");
        continue;
      }
      json state = level == 0 ? json{{"on", false}} : json{{"on", true}, {"brightness", level}};
      if (auto s = command(d, state)) done.push_back(*s);
    }
    report(done);
  }

  void step(const json& home, const std::string& phrase, int delta) {
    std::vector<json> devices = lit_ones(lights_of(pick(home, phrase)));
    remember(devices);
    std::vector<json> done;
    for (const json& d : devices) {
      const bool on = d.value("on", json()).is_boolean() && d["on"].get<bool>();
      const std::string name = d.value("name", "");
      if (!d.value("dimmable", false)) {
        // "It's too dark in here" with a plain light off: switching it on is what helps.
        if (delta > 0 && !on) {
          if (auto s = command(d, json{{"on", true}})) done.push_back(*s);
        } else {
          robot().say(delta > 0 ? "The " + name + " is already on, as bright as it goes."
                                : "The " + name + " can't be dimmed.");
        }
        continue;
      }
      if (delta < 0 && !on) {  // dimming a light that is off must not switch it on
        robot().say("The " + name + " is already off.");
        continue;
      }
      const int current =
          on && d.value("brightness", json()).is_number_integer() ? d["brightness"].get<int>() : 0;
      // Absolute, so the command means the same if it were delivered twice.
      const int level = std::clamp(current + delta, delta > 0 ? kStep : 5, 100);
      if (auto s = command(d, json{{"on", true}, {"brightness", level}})) done.push_back(*s);
    }
    report(done);
  }

  // "Dim the lights to 30 percent", "brighter please" with several lights in reach: the
  // ones that are on are meant (a light that is off in another room stays off); all of
  // them when none is on.
  static std::vector<json> lit_ones(std::vector<json> devices) {
    if (devices.size() < 2) return devices;
    std::vector<json> on;
    for (const json& d : devices) {
      if (d.value("on", json()) == json(true)) on.push_back(d);
    }
    return on.empty() ? devices : on;
  }

  // More or less light is the lights' business: "it's too dark" after "switch everything
  // off in the living room" must not switch the tv back on. Others only when no light fits.
  static std::vector<json> lights_of(std::vector<json> devices) {
    std::vector<json> lights;
    for (const json& d : devices) {
      if (d.value("type", "light") == "light") lights.push_back(d);
    }
    return lights.empty() ? devices : lights;
  }

  // "Is the fan on?" is answered "Yes, ..."; "what is the thermostat set to?" is not.
  static bool yes_no_question(const std::string& utterance) {
    const std::vector<std::string> w = marvin_home_skill::words(utterance);
    static const std::set<std::string> kOpeners = {"is",  "are", "did",   "was", "were",
                                                   "has", "have", "do",   "can", "could",
                                                   "check", "see"};
    return !w.empty() && kOpeners.count(w.front()) > 0;
  }

  void query(const json& home, const std::string& phrase, bool yes_no) {
    std::vector<json> devices = pick(home, phrase, true);
    remember(devices);
    if (devices.size() == 1) {
      const json on = devices[0].value("on", json());
      std::string text = describe(devices[0]);
      if (yes_no && on.is_boolean()) text = (on.get<bool>() ? "Yes, " : "No, ") + text;
      robot().say(capital(text) + ".");
      return;
    }
    report(devices);
  }

  // The room a request names: "" for the whole home (none named, or "the house"); the
  // robot's room for "in here".
  static std::string named_room(const json& home, std::string room) {
    room = marvin_home_skill::tidy(room);
    if (marvin_home_skill::means_this_room(room)) return home.value("room", "");
    const std::vector<std::string> said = marvin_home_skill::words(room);
    if (std::all_of(said.begin(), said.end(), marvin_home_skill::everywhere_word)) return "";
    return room;
  }

  // "Switch everything off" with no room named is the whole home (going to bed, going out);
  // "in here" is the robot's room.
  void all_off(const json& home, std::string room) {
    room = named_room(home, room);
    const bool everywhere = room.empty();
    if (everywhere) room = "house";
    std::vector<json> devices;
    for (const json& d : home["devices"]) {
      if (is_thermostat(d)) continue;  // the heating only when named (see the top)
      if (everywhere || d.value("room", "") == room) devices.push_back(d);
    }
    if (devices.empty()) {
      robot().say("I don't know any devices in the " + room + ".");
      return;
    }
    remember(devices);
    int failed = 0;
    for (const json& d : devices) {
      if (!command(d, json{{"on", false}})) ++failed;
    }
    if (failed == 0) robot().say("Everything in the " + room + " is off.");
  }

  // "Is anything still on?" / "is everything off?": the lights and switches that are on,
  // in the room named or in the whole home. The heating is not counted: it is meant to
  // stay on.
  void what_is_on(const json& home, const std::string& room_said, bool asked_all_off,
                  bool yes_no) {
    const std::string room = named_room(home, room_said);
    std::vector<json> on;
    bool known_room = room.empty();
    for (const json& d : home["devices"]) {
      if (!room.empty() && d.value("room", "") != room) continue;
      known_room = true;
      if (!is_thermostat(d) && d.value("on", json()) == json(true)) on.push_back(d);
    }
    if (!known_room) return robot().say("I don't know any devices in the " + room + ".");
    remember(on);  // "turn them off"
    if (on.empty()) {
      // "Is anything on?" No; "is everything off?" Yes; "what lights are on?" neither.
      const std::string everything = std::string(asked_all_off ? "Yes, everything"
                                                 : yes_no       ? "No, everything"
                                                                : "Everything") +
                                     (room.empty() ? "" : " in the " + room) + " is off.";
      return robot().say(everything);
    }
    robot().say(asked_all_off ? "No, " + states(on) + "." : capital(states(on)) + ".");
  }

  // --- the heating ---------------------------------------------------------------------

  // "Set the bedroom to 19": only a room named, and a number its thermostat takes, is the
  // heating (nobody sets the lights of a room to 19 percent in those words).
  static bool room_set_point(const json& home, const std::string& phrase, int level) {
    const std::string room = marvin_home_skill::tidy(phrase);
    if (room.empty() || level < 0) return false;
    for (const json& d : home["devices"]) {
      if (is_thermostat(d) && d.value("room", "") == room &&
          level >= d.value("min_temperature", 5.0) && level <= d.value("max_temperature", 30.0)) {
        return true;
      }
    }
    return false;
  }

  // The thermostats `phrase` means: a room ("in the bedroom"), a thermostat's name or "the
  // heating"; nothing said: the one in the robot's room, else the home's only one, else
  // the skill asks. Empty after telling the user.
  std::vector<json> pick_thermostats(const json& home, const std::string& phrase) {
    json thermostats = json::array();
    for (const json& d : home["devices"]) {
      if (is_thermostat(d)) thermostats.push_back(d);
    }
    if (thermostats.empty()) {
      robot().say("I can't change the temperature: none of your devices is a thermostat.");
      return {};
    }
    if (std::vector<json> last = last_thermostats(home, phrase); !last.empty()) return last;
    std::string said = marvin_home_skill::tidy(phrase);
    if (marvin_home_skill::means_this_room(said) || said == "it" || said == "them") said.clear();
    const std::string here = home.value("room", "");
    if (said.empty()) {
      std::vector<json> local;
      for (const json& d : thermostats) {
        if (d.value("room", "") == here) local.push_back(d);
      }
      if (!local.empty()) return local;
      if (thermostats.size() == 1) return {thermostats[0]};
      said = "thermostat";
    }
    if (marvin_home_skill::resolve(thermostats, said, here).matches.empty()) {
      robot().say("I don't know a thermostat for the " + said + ".");
      return {};
    }
    return pick(json{{"devices", thermostats}, {"room", here}}, said);
  }

  // "Turn it up" after a request about the heating: the thermostats of that request (empty
  // when `phrase` is not "it" or "them", or the last request was about something else).
  std::vector<json> last_thermostats(const json& home, const std::string& phrase) const {
    const std::string said = marvin_home_skill::tidy(phrase);
    if ((said != "it" && said != "them") || !last_ || last_->empty()) return {};
    std::vector<json> out;
    for (const std::string& id : *last_) {
      for (const json& d : home["devices"]) {
        if (d["id"] == id) {
          if (!is_thermostat(d)) return {};
          out.push_back(d);
        }
      }
    }
    return out;
  }

  // "I'm cold": the set point a step up (the heating on if it was off); "I'm hot": a step
  // down, but a thermostat that is off stays off.
  void change_warmth(const json& home, const std::string& phrase, bool warmer) {
    std::vector<json> thermostats = pick_thermostats(home, phrase);
    remember(thermostats);
    std::vector<json> done;
    for (const json& t : thermostats) {
      const std::string name = t.value("name", "");
      const bool on = !t.value("on", json()).is_boolean() || t["on"].get<bool>();
      if (!warmer && !on) {
        robot().say("The " + name + " is already off.");
        continue;
      }
      const json target = t.value("target_temperature", json());
      if (!target.is_number()) {
        robot().say("The " + name + " hasn't told me its setting, so I can't turn it " +
                    (warmer ? "up." : "down."));
        continue;
      }
      const double low = t.value("min_temperature", 5.0), high = t.value("max_temperature", 30.0);
      const double now = target.get<double>();
      const double want = std::clamp(now + (warmer ? 1 : -1) * marvin_home_skill::kWarmthStep,
                                     low, high);
      json state{{"target_temperature", want}};
      if (warmer && !on) state["on"] = true;
      if (want == now && on) {
        robot().say("The " + name + " is already at its " + (warmer ? "highest" : "lowest") +
                    " setting, " + degrees(now) + " degrees.");
        continue;
      }
      if (auto s = command(t, state)) done.push_back(*s);
    }
    report_heating(done);
  }

  // "set the heating to 21 degrees"
  void set_temperature(const json& home, const std::string& phrase, int level) {
    std::vector<json> thermostats = pick_thermostats(home, phrase);
    remember(thermostats);
    std::vector<json> done;
    for (const json& t : thermostats) {
      const double low = t.value("min_temperature", 5.0), high = t.value("max_temperature", 30.0);
      if (level < low || level > high) {
        robot().say("I can set the " + t.value("name", "") + " from " + degrees(low) + " to " +
                    degrees(high) + " degrees.");
        continue;
      }
      json state{{"target_temperature", level}};
      if (t.value("switchable", false) && t.value("on", json()) != json(true)) state["on"] = true;
      if (auto s = command(t, state)) done.push_back(*s);
    }
    report_heating(done);
  }

  // "What's the temperature?": what the thermostats measure, the robot's room first (or the
  // room or thermostat named), with how each is set.
  void temperature(const json& home, const std::string& phrase) {
    std::vector<json> measuring;
    for (const json& d : home["devices"]) {
      if (is_thermostat(d) && d.value("temperature", json()).is_number()) measuring.push_back(d);
    }
    if (measuring.empty()) {
      robot().say("Sorry, I can't tell the temperature: none of your devices measures it.");
      return;
    }
    std::string said = marvin_home_skill::tidy(phrase);
    if (marvin_home_skill::means_this_room(said)) said.clear();
    const std::string here = home.value("room", "");
    std::vector<json> chosen;
    if (!said.empty()) {
      for (std::size_t i : marvin_home_skill::resolve(measuring, said, here).matches)
        chosen.push_back(measuring[i]);
      if (chosen.empty()) {
        bool a_room = false;  // of this home
        for (const json& d : home["devices"]) a_room = a_room || d.value("room", "") == said;
        robot().say(a_room ? "I have no thermometer in the " + said + "."
                           : "I only know the temperature indoors, from your thermostats, and "
                             "nothing about the weather.");
        return;
      }
    } else {
      for (const json& d : measuring) {
        if (d.value("room", "") == here) chosen.push_back(d);
      }
    }
    std::string text;
    if (chosen.empty()) {  // every room the robot can tell, saying it cannot tell this one
      chosen = measuring;
      if (!here.empty()) text = "I have no thermometer in the " + here + ".";
    }
    remember(chosen);
    for (const json& d : chosen) {
      if (!text.empty()) text += " ";
      text += marvin_home_skill::room_temperature(d) + " " +
              capital(marvin_home_skill::thermostat_state(d)) + ".";
    }
    robot().say(text);
  }

  // "The living room thermostat is on, set to 22 degrees. It's 19.5 degrees in the living
  // room."
  void report_heating(const std::vector<json>& done) {
    std::string text;
    for (const json& d : done) {
      if (!text.empty()) text += " ";
      text += capital(marvin_home_skill::thermostat_state(d)) + ".";
      if (std::string t = marvin_home_skill::room_temperature(d); !t.empty()) text += " " + t;
    }
    if (!text.empty()) robot().say(text);
  }

  std::optional<std::vector<std::string>> last_;  // "it": the devices of the last request
};

}  // namespace

MARVIN_SKILL(HomeSkill, "home")
