// Built-in skill "home": lights, fans and switches of the home by voice, through the Robot
// API's smarthome_devices and smarthome_set (API 1.2).
//   "turn on the bedroom light"            "switch off the fan"
//   "dim the living room lights to 30 percent"   "make it brighter"
//   "is the kitchen light on?"             "turn everything off in the bedroom"
//   "turn off all the lights" (every room) "turn everything off in the house"
// The device comes from the room named (or the room the robot is in) and the name; when
// that leaves several, the skill asks ("The hall light or the bedroom light?"). Every
// "it's on" is said after the device itself reported it (smarthome_set returns then);
// otherwise the skill says the device did not answer, or that the home's hub is not
// reachable (the host keeps reconnecting meanwhile).
#include <algorithm>
#include <cctype>
#include <marvin/skill.hpp>
#include <optional>
#include <string>
#include <vector>

#include "common/spoken_text.h"
#include "resolve.h"

namespace {

using marvin::builtin::capital;

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
    if (intent == "set_level") {
      int level = request.slots.value("level", -1);
      return set_level(*home, text("device"), level);
    }
    if (intent == "brighter" || intent == "dimmer") {
      return step(*home, text("device"), intent == "brighter" ? kStep : -kStep);
    }
    if (intent == "query") {
      // Lights, fans and switches say on, off and how bright; none of them is a thermometer.
      if (asks_temperature(request.utterance)) {
        robot().say("Sorry, I can't tell the temperature: none of your devices measures it.");
        return;
      }
      return query(*home, text("device"));
    }
    if (intent == "all_off") return all_off(*home, text("room"));
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
    if (done.empty()) return;
    // Several now alike ("The hall light, the kitchen light and the bedroom light are off."):
    // each name once, the state once.
    const json first_on = done[0].value("on", json());
    const bool alike = done.size() > 1 && first_on.is_boolean() &&
                       std::all_of(done.begin(), done.end(), [&](const json& d) {
                         return d.value("on", json()) == first_on &&
                                describe(d) == "the " + d.value("name", "") +
                                                   (first_on.get<bool>() ? " is on" : " is off");
                       });
    if (alike) {
      std::string names;
      for (std::size_t i = 0; i < done.size(); ++i) {
        if (i > 0) names += i + 1 == done.size() ? " and " : ", ";
        names += "the " + done[i].value("name", "");
      }
      robot().say(capital(names) + (first_on.get<bool>() ? " are on." : " are off."));
      return;
    }
    std::string text;
    for (std::size_t i = 0; i < done.size(); ++i) {
      if (i > 0) text += i + 1 == done.size() ? " and " : ", ";
      text += describe(done[i]);
    }
    robot().say(capital(text) + ".");
  }

  void switch_devices(const json& home, const std::string& phrase, bool on) {
    std::vector<json> devices = pick(home, phrase);
    remember(devices);
    std::vector<json> done;
    for (const json& d : devices) {
      if (auto state = command(d, json{{"on", on}})) done.push_back(*state);
    }
    report(done);
  }

  void set_level(const json& home, const std::string& phrase, int level) {
    if (level < 0 || level > 100) {
      robot().say("I can set a light from 0 to 100 percent.");
      return;
    }
    std::vector<json> devices = pick(home, phrase);
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
    std::vector<json> devices = pick(home, phrase);
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

  void query(const json& home, const std::string& phrase) {
    std::vector<json> devices = pick(home, phrase, true);
    remember(devices);
    if (devices.size() == 1) {
      const json on = devices[0].value("on", json());
      std::string text = describe(devices[0]);
      if (on.is_boolean()) text = (on.get<bool>() ? "Yes, " : "No, ") + text;
      robot().say(capital(text) + ".");
      return;
    }
    report(devices);
  }

  void all_off(const json& home, std::string room) {
    room = marvin_home_skill::tidy(room);
    if (room.empty() || room == "here" || room == "this room") room = home.value("room", "");
    // "everything off in the house": every room.
    const std::vector<std::string> said = marvin_home_skill::words(room);
    const bool everywhere =
        !said.empty() && std::all_of(said.begin(), said.end(), marvin_home_skill::everywhere_word);
    if (everywhere) room = "house";
    std::vector<json> devices;
    for (const json& d : home["devices"]) {
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

  std::optional<std::vector<std::string>> last_;  // "it": the devices of the last request
};

}  // namespace

MARVIN_SKILL(HomeSkill, "home")
