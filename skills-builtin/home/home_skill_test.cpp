// The home skill with the MockRobot's scripted devices: what it says and what it sends.
#include <doctest/doctest.h>

#include <fstream>
#include <marvin/testing/mock_robot.hpp>
#include <marvin/testing/skill_harness.hpp>
#include <nlohmann/json.hpp>

#include "heating.h"
#include "resolve.h"

using Lines = std::vector<std::string>;
using nlohmann::json;

namespace {

void world(marvin::testing::SkillHarness& h) {
  auto& r = h.robot();
  r.add_device(R"({"id": "hall", "name": "hall light", "room": "hall"})");
  r.add_device(
      R"({"id": "lamp", "name": "living room lamp", "room": "living room", "dimmable": true,
                   "aliases": ["big lamp"]})");
  r.add_device(
      R"({"id": "kitchen", "name": "kitchen light", "room": "kitchen", "dimmable": true})");
  r.add_device(R"({"id": "bed", "name": "bedroom light", "room": "bedroom", "dimmable": true})");
  r.add_device(R"({"id": "fan", "name": "bedroom fan", "room": "bedroom", "type": "fan"})");
  r.add_device(R"({"id": "bath", "name": "bathroom light", "room": "bathroom"})");
  r.add_device(R"({"id": "tv", "name": "tv", "room": "living room", "type": "switch"})");
}

// The smart-home commands among the robot's actions (the harness adds light changes).
Lines sent(marvin::testing::SkillHarness& h) {
  Lines out;
  for (const std::string& a : h.robot().actions()) {
    if (a.rfind("smarthome_set", 0) == 0) out.push_back(a);
  }
  return out;
}

json state(marvin::testing::SkillHarness& h, const std::string& id) {
  return json::parse(*h.robot().device(id));
}

TEST_CASE("turn on the bedroom light; switch off the fan; is the kitchen light on") {
  marvin::testing::SkillHarness h(HOME_SKILL_DIR);
  world(h);
  CHECK(h.intent_of("turn on the bedroom light") == "home/turn_on");
  CHECK(h.say("turn on the bedroom light") == Lines{"The bedroom light is on."});
  CHECK(state(h, "bed")["on"] == true);
  CHECK(sent(h) == Lines{R"(smarthome_set bed {"on":true})"});
  h.robot().clear();
  CHECK(h.say("switch on the fan") == Lines{"The bedroom fan is on."});
  CHECK(h.say("switch off the fan") == Lines{"The bedroom fan is off."});
  CHECK(h.say("is the kitchen light on?") == Lines{"No, the kitchen light is off."});
  CHECK(h.say("is the fan on") == Lines{"No, the bedroom fan is off."});
  CHECK(h.say("switch on the big lamp") == Lines{"The living room lamp is on."});
  // No device of this home measures temperature: said so, not the lamps' state.
  h.robot().clear();
  CHECK(h.say("what's the temperature in the living room") ==
        Lines{"Sorry, I can't tell the temperature: none of your devices measures it."});
  CHECK(sent(h).empty());
}

TEST_CASE("dim the living room lights to 30 percent, then make it brighter") {
  marvin::testing::SkillHarness h(HOME_SKILL_DIR);
  world(h);
  CHECK(h.intent_of("dim the living room lights to 30 percent") == "home/set_level");
  CHECK(h.say("dim the living room lights to 30 percent") ==
        Lines{"The living room lamp is on, at 30 percent."});
  CHECK(state(h, "lamp")["brightness"] == 30);
  CHECK(h.intent_of("make it brighter") == "home/brighter");
  CHECK(h.say("make it brighter") == Lines{"The living room lamp is on, at 55 percent."});
  CHECK(sent(h).back() == R"(smarthome_set lamp {"brightness":55,"on":true})");
  CHECK(h.say("dim the tv to 20 percent") == Lines{"The tv can't be dimmed."});
  // A room named with a level: what dims there (not the tv beside the lamp), no question.
  h.robot().clear();
  CHECK(h.say("set the living room to 50 percent") ==
        Lines{"The living room lamp is on, at 50 percent."});
  CHECK(h.robot().asked().empty());
}

TEST_CASE("more or less light: the lights that are on, and lights only") {
  marvin::testing::SkillHarness h(HOME_SKILL_DIR);
  world(h);
  h.robot().set_room("hall");
  h.say("turn on the living room lamp");
  // The lamp is the only light on: "the lights" to 30 percent leave the dark rooms dark.
  h.robot().clear();
  CHECK(h.say("dim the lights to 30 percent") ==
        Lines{"The living room lamp is on, at 30 percent."});
  CHECK(sent(h) == Lines{R"(smarthome_set lamp {"brightness":30,"on":true})"});
  CHECK(h.say("brighter please") == Lines{"The living room lamp is on, at 55 percent."});
  CHECK(state(h, "kitchen")["on"] == false);
  // After everything in the living room went off, "it's too dark in here" is the light of
  // the robot's room, and never the tv that went off with the lamp.
  h.say("switch everything off in the living room");
  h.robot().clear();
  CHECK(h.say("it's too dark in here") == Lines{"The hall light is on."});
  CHECK(sent(h) == Lines{R"(smarthome_set hall {"on":true})"});
  h.robot().clear();
  h.say("turn off the lamp and the tv");
  CHECK(h.say("more light please") == Lines{"The living room lamp is on, at 25 percent."});
  CHECK(state(h, "tv")["on"] == false);
}

TEST_CASE("brighter and dimmer on a light that cannot dim, or that is off") {
  marvin::testing::SkillHarness h(HOME_SKILL_DIR);
  world(h);  // the robot is in the hall; the hall light only switches
  CHECK(h.say("make the hall light brighter") == Lines{"The hall light is on."});
  CHECK(state(h, "hall")["on"] == true);
  CHECK(h.say("make the hall light brighter") ==
        Lines{"The hall light is already on, as bright as it goes."});
  CHECK(h.say("make the hall light dimmer") == Lines{"The hall light can't be dimmed."});
  h.robot().clear();
  CHECK(h.say("make the kitchen light dimmer") == Lines{"The kitchen light is already off."});
  CHECK(state(h, "kitchen")["on"] == false);
  CHECK(sent(h).empty());
}

TEST_CASE("turn everything off in the bedroom") {
  marvin::testing::SkillHarness h(HOME_SKILL_DIR);
  world(h);
  h.say("turn on the bedroom light");
  h.say("turn on the fan");
  h.robot().clear();
  CHECK(h.intent_of("turn everything off in the bedroom") == "home/all_off");
  CHECK(h.say("turn everything off in the bedroom") == Lines{"Everything in the bedroom is off."});
  CHECK(sent(h) == Lines{R"(smarthome_set bed {"on":false})", R"(smarthome_set fan {"on":false})"});
  CHECK(state(h, "fan")["on"] == false);
}

TEST_CASE("the big light: a describing word no device is named with leaves the room's light") {
  marvin::testing::SkillHarness h(HOME_SKILL_DIR);
  world(h);
  h.robot().set_room("kitchen");
  CHECK(h.say("turn the big light on") == Lines{"The kitchen light is on."});
  CHECK(h.say("switch off the main light in the bedroom") == Lines{"The bedroom light is off."});
  // An alias with the word still names its device; a word that describes nothing here
  // ("red") is no light of this room.
  CHECK(h.say("turn on the big lamp") == Lines{"The living room lamp is on."});
  CHECK(h.say("turn on the red light") == Lines{"I don't know a device called the red light."});
  CHECK(state(h, "kitchen")["on"] == true);
}

TEST_CASE("all the lights: every light in every room, not only this room's") {
  marvin::testing::SkillHarness h(HOME_SKILL_DIR);
  world(h);
  h.robot().set_room("hall");
  CHECK(h.say("turn on all the lights") ==
        Lines{"The hall light, the living room lamp, the kitchen light, the bedroom light and "
              "the bathroom light are on."});
  CHECK(sent(h) == Lines{R"(smarthome_set hall {"on":true})", R"(smarthome_set lamp {"on":true})",
                         R"(smarthome_set kitchen {"on":true})", R"(smarthome_set bed {"on":true})",
                         R"(smarthome_set bath {"on":true})"});
  CHECK(state(h, "fan")["on"] == false);  // a fan is no light
  h.robot().clear();
  CHECK(h.say("switch off every light") ==
        Lines{"The hall light, the living room lamp, the kitchen light, the bedroom light and "
              "the bathroom light are off."});
  CHECK(sent(h).size() == 5);
  h.say("turn on the fan");
  h.say("turn on the tv");
  h.robot().clear();
  CHECK(h.say("turn everything off in the house") == Lines{"Everything in the house is off."});
  CHECK(sent(h) == Lines{R"(smarthome_set hall {"on":false})", R"(smarthome_set lamp {"on":false})",
                         R"(smarthome_set kitchen {"on":false})",
                         R"(smarthome_set bed {"on":false})", R"(smarthome_set fan {"on":false})",
                         R"(smarthome_set bath {"on":false})", R"(smarthome_set tv {"on":false})"});
  // Without "all", "the lights" are still this room's.
  h.robot().clear();
  CHECK(h.say("turn on the lights") == Lines{"The hall light is on."});
}

TEST_CASE("an ambiguous light is asked about; the answer picks it") {
  marvin::testing::SkillHarness h(HOME_SKILL_DIR);
  world(h);
  h.robot().set_room("study");  // no light here, so "the light" could be any
  Lines said = h.say("turn on the light", {"the kitchen one"});
  REQUIRE(said.size() == 2);
  CHECK(said[0] ==
        "The hall light, the living room lamp, the kitchen light, the bedroom light or the "
        "bathroom light?");
  CHECK(said[1] == "The kitchen light is on.");
  CHECK(sent(h) == Lines{R"(smarthome_set kitchen {"on":true})"});

  h.robot().clear();
  CHECK(h.say("turn off the bedroom thing", {"the bedroom fan"}) ==
        Lines{"The bedroom light or the bedroom fan?", "The bedroom fan is off."});
  // The room the robot is in settles it without a question.
  h.robot().set_room("bedroom");
  CHECK(h.say("turn on the light") == Lines{"The bedroom light is on."});
}

TEST_CASE("a device that does not answer, and an unreachable hub, are said as such") {
  marvin::testing::SkillHarness h(HOME_SKILL_DIR);
  world(h);
  h.robot().set_device_answers("fan", false);
  CHECK(h.say("turn on the fan") == Lines{"The bedroom fan didn't answer."});
  CHECK(state(h, "fan")["on"] == false);
  h.robot().set_broker_reachable(false);
  CHECK(h.say("turn on the kitchen light") ==
        Lines{"I can't reach the home's hub right now, so the kitchen light is unchanged. "
              "I'll keep trying to reconnect."});
  CHECK(state(h, "kitchen")["on"] == false);
  CHECK(h.say("turn on the garage door") == Lines{"I don't know a device called the garage door."});
}

TEST_CASE("resolve: rooms, kinds, plurals") {
  json devices = json::parse(R"([
    {"name": "hall light", "room": "hall", "type": "light"},
    {"name": "living room lamp", "room": "living room", "type": "light"},
    {"name": "bedroom light", "room": "bedroom", "type": "light"},
    {"name": "bedroom fan", "room": "bedroom", "type": "fan"},
    {"name": "tv", "room": "living room", "type": "switch"}])");
  using marvin_home_skill::resolve;
  CHECK(resolve(devices, "the living room lights", "").matches == std::vector<std::size_t>{1});
  CHECK(resolve(devices, "the living room lights", "").plural);
  CHECK(resolve(devices, "fan", "hall").matches == std::vector<std::size_t>{3});
  CHECK(resolve(devices, "the lights in the bedroom", "").matches == std::vector<std::size_t>{2});
  CHECK(resolve(devices, "the light", "hall").matches == std::vector<std::size_t>{0});
  CHECK(resolve(devices, "the light", "kitchen").matches.size() == 3);
  CHECK(resolve(devices, "the tv", "").matches == std::vector<std::size_t>{4});
  CHECK(resolve(devices, "the toaster", "").matches.empty());
  const auto all = resolve(devices, "all the lights", "hall");
  CHECK(all.matches == std::vector<std::size_t>{0, 1, 2});
  CHECK(all.plural);
  CHECK(resolve(devices, "the lights in the house", "hall").matches.size() == 3);
  CHECK(resolve(devices, "both bedroom things", "hall").matches == std::vector<std::size_t>{2, 3});
  // A device named a lamp: "the lamp" is it, from any room; the lamp is still a light.
  CHECK(resolve(devices, "the lamp", "hall").matches == std::vector<std::size_t>{1});
  CHECK(resolve(devices, "the lamps", "bedroom").matches == std::vector<std::size_t>{1});
  CHECK(resolve(devices, "the light", "living room").matches == std::vector<std::size_t>{1});
  // With no device named a lamp, "lamp" is any light (the room's first).
  const json no_lamp = json::parse(R"([{"name": "hall light", "room": "hall", "type": "light"},
    {"name": "bedroom light", "room": "bedroom", "type": "light"}])");
  CHECK(resolve(no_lamp, "the lamp", "bedroom").matches == std::vector<std::size_t>{1});
}

TEST_CASE("two devices joined by and: both switched; one unknown: neither, and it is named") {
  marvin::testing::SkillHarness h(HOME_SKILL_DIR);
  world(h);
  CHECK(h.say("turn on the kitchen light and the hall light") ==
        Lines{"The kitchen light and the hall light are on."});
  CHECK(sent(h) == Lines{R"(smarthome_set kitchen {"on":true})", R"(smarthome_set hall {"on":true})"});
  h.robot().clear();
  CHECK(h.say("switch off the tv and the lamp") == Lines{"The tv and the living room lamp are off."});
  CHECK(sent(h) == Lines{R"(smarthome_set tv {"on":false})", R"(smarthome_set lamp {"on":false})"});
  h.robot().clear();
  CHECK(h.say("turn on the bedroom light and the garage light") ==
        Lines{"I don't know a device called the garage light."});
  CHECK(sent(h).empty());
  CHECK(state(h, "bed")["on"] == false);
  // "them" after it: both again.
  h.say("turn on the kitchen light and the hall light");
  h.robot().clear();
  CHECK(h.say("turn them off") == Lines{"The kitchen light and the hall light are off."});
}

// world() plus a thermostat in the living room and one in the bedroom (5 to 30 degrees).
void heated_world(marvin::testing::SkillHarness& h) {
  world(h);
  auto& r = h.robot();
  r.add_device(R"({"id": "lrt", "name": "living room thermostat", "room": "living room",
                   "type": "thermostat", "on": true, "target_temperature": 20, "temperature": 19.5,
                   "min_temperature": 5, "max_temperature": 30, "switchable": true})");
  r.add_device(R"({"id": "bt", "name": "bedroom thermostat", "room": "bedroom",
                   "type": "thermostat", "on": false, "target_temperature": 18, "temperature": 17,
                   "min_temperature": 5, "max_temperature": 30, "switchable": true})");
}

TEST_CASE("I'm cold: the thermostat of the robot's room a degree up, the room's temperature said") {
  marvin::testing::SkillHarness h(HOME_SKILL_DIR);
  heated_world(h);
  h.robot().set_room("living room");
  CHECK(h.intent_of("i'm cold") == "home/warmer");
  CHECK(h.say("i'm cold") ==
        Lines{"The living room thermostat is on, set to 21 degrees. It's 19.5 degrees in the "
              "living room."});
  CHECK(sent(h) == Lines{R"(smarthome_set lrt {"target_temperature":21.0})"});
  // "Turn it down" is the same thermostat, not a lamp.
  CHECK(h.say("turn it down") ==
        Lines{"The living room thermostat is on, set to 20 degrees. It's 19.5 degrees in the "
              "living room."});
  // How much is no part of the name: "the heating a bit" is the heating.
  CHECK(h.say("turn the heating up a bit") ==
        Lines{"The living room thermostat is on, set to 21 degrees. It's 19.5 degrees in the "
              "living room."});
  // A heating that is off: warmer switches it on; cooler leaves it off and sends nothing.
  h.robot().clear();
  CHECK(h.say("it's too hot in the bedroom") == Lines{"The bedroom thermostat is already off."});
  CHECK(sent(h).empty());
  CHECK(h.say("make it warmer in the bedroom") ==
        Lines{"The bedroom thermostat is on, set to 19 degrees. It's 17 degrees in the bedroom."});
  CHECK(state(h, "bt")["on"] == true);
}

TEST_CASE("set the heating to 21 degrees; out of range is refused and nothing is sent") {
  marvin::testing::SkillHarness h(HOME_SKILL_DIR);
  heated_world(h);
  h.robot().set_room("bedroom");
  CHECK(h.say("set the heating to 40 degrees") ==
        Lines{"I can set the bedroom thermostat from 5 to 30 degrees."});
  CHECK(sent(h).empty());
  CHECK(state(h, "bt")["target_temperature"] == 18);
  CHECK(h.say("set the heating to 21 degrees") ==
        Lines{"The bedroom thermostat is on, set to 21 degrees. It's 17 degrees in the bedroom."});
  CHECK(sent(h) == Lines{R"(smarthome_set bt {"on":true,"target_temperature":21})"});
  // "Set the lamp to 40 percent" is still the lamp's brightness.
  h.robot().clear();
  CHECK(h.say("set the living room lamp to 40 percent") ==
        Lines{"The living room lamp is on, at 40 percent."});
}

TEST_CASE("what's the temperature: the robot's room, else every room it can tell") {
  marvin::testing::SkillHarness h(HOME_SKILL_DIR);
  heated_world(h);
  h.robot().set_room("living room");
  CHECK(h.say("what's the temperature in here") ==
        Lines{"It's 19.5 degrees in the living room. The living room thermostat is on, set to 20 "
              "degrees."});
  CHECK(h.say("how warm is it in the bedroom") ==
        Lines{"It's 17 degrees in the bedroom. The bedroom thermostat is off."});
  h.robot().set_room("kitchen");
  CHECK(h.say("how warm is it") ==
        Lines{"I have no thermometer in the kitchen. It's 19.5 degrees in the living room. The "
              "living room thermostat is on, set to 20 degrees. It's 17 degrees in the bedroom. "
              "The bedroom thermostat is off."});
  CHECK(h.say("what's the temperature in the kitchen") ==
        Lines{"I have no thermometer in the kitchen."});
  CHECK(sent(h).empty());
}

TEST_CASE("everything off leaves the heating on; turning the heating off is said") {
  marvin::testing::SkillHarness h(HOME_SKILL_DIR);
  heated_world(h);
  CHECK(h.say("turn everything off in the living room") ==
        Lines{"Everything in the living room is off."});
  CHECK(state(h, "lrt")["on"] == true);
  CHECK(h.say("turn off the heating in the living room") ==
        Lines{"The living room thermostat is off."});
  CHECK(state(h, "lrt")["on"] == false);
  CHECK(h.say("is the heating on in the living room") ==
        Lines{"No, the living room thermostat is off."});
}

TEST_CASE("switch everything off with no room named: the whole home, the heating left on") {
  marvin::testing::SkillHarness h(HOME_SKILL_DIR);
  heated_world(h);
  h.robot().set_room("hall");
  h.say("turn on the kitchen light");
  h.say("turn on the tv");
  h.robot().clear();
  CHECK(h.say("switch everything off") == Lines{"Everything in the house is off."});
  CHECK(state(h, "kitchen")["on"] == false);
  CHECK(state(h, "tv")["on"] == false);
  CHECK(state(h, "lrt")["on"] == true);
  h.say("turn on the kitchen light");
  h.say("turn on the hall light");
  CHECK(h.say("turn everything off in here") == Lines{"Everything in the hall is off."});
  CHECK(state(h, "hall")["on"] == false);
  CHECK(state(h, "kitchen")["on"] == true);  // not the robot's room
}

TEST_CASE("is anything still on: what is on, in the home or a room; the heating not counted") {
  marvin::testing::SkillHarness h(HOME_SKILL_DIR);
  heated_world(h);
  h.robot().set_room("hall");
  CHECK(h.intent_of("is anything still on") == "home/what_is_on");
  CHECK(h.intent_of("which lights are on") == "home/what_is_on");
  CHECK(h.intent_of("did I leave anything on") == "home/what_is_on");
  CHECK(h.intent_of("is everything off") == "home/what_is_on");
  CHECK(h.intent_of("is the kitchen light on") == "home/query");
  CHECK(h.say("is anything still on") == Lines{"No, everything is off."});
  CHECK(h.say("is everything off?") == Lines{"Yes, everything is off."});
  CHECK(h.say("what lights are on") == Lines{"Everything is off."});  // no yes/no asked
  h.say("turn on the kitchen light");
  h.say("turn on the tv");
  h.robot().clear();
  CHECK(h.say("which lights are on") == Lines{"The kitchen light and the tv are on."});
  CHECK(h.say("is everything off?") == Lines{"No, the kitchen light and the tv are on."});
  CHECK(h.say("is anything on in the kitchen") == Lines{"The kitchen light is on."});
  CHECK(h.say("are any lights on in the bedroom") == Lines{"No, everything in the bedroom is off."});
  CHECK(h.say("what's on in the garage") == Lines{"I don't know any devices in the garage."});
  CHECK(sent(h).empty());  // asking changes nothing
  // "Them" are the devices just named.
  CHECK(h.say("which lights are on") == Lines{"The kitchen light and the tv are on."});
  CHECK(h.say("turn them off") == Lines{"The kitchen light and the tv are off."});
  CHECK(state(h, "kitchen")["on"] == false);
}

TEST_CASE("set the bedroom to 19: a room alone and a set point its thermostat takes") {
  marvin::testing::SkillHarness h(HOME_SKILL_DIR);
  heated_world(h);
  CHECK(h.say("set the bedroom to 19") ==
        Lines{"The bedroom thermostat is on, set to 19 degrees. It's 17 degrees in the bedroom."});
  CHECK(state(h, "bt")["target_temperature"] == 19);
  CHECK(state(h, "bed")["on"] != json(true));  // the light untouched
  // Out of the thermostat's range, or a device named: the lights as before.
  CHECK(h.say("set the bedroom light to 19") == Lines{"The bedroom light is on, at 19 percent."});
  CHECK(state(h, "bt")["target_temperature"] == 19);
}

TEST_CASE("no thermostat: warmth requests say so and send nothing") {
  marvin::testing::SkillHarness h(HOME_SKILL_DIR);
  world(h);
  CHECK(h.say("i'm cold") ==
        Lines{"I can't change the temperature: none of your devices is a thermostat."});
  CHECK(sent(h).empty());
}

TEST_CASE("heating words and degrees") {
  using marvin_home_skill::about_heating;
  CHECK(about_heating("turn up the heating"));
  CHECK(about_heating("set it to 21 degrees"));
  CHECK_FALSE(about_heating("turn up the lamp"));
  CHECK_FALSE(about_heating("set the kitchen light to 30 percent"));
  CHECK(marvin_home_skill::degrees(21.0) == "21");
  CHECK(marvin_home_skill::degrees(19.5) == "19.5");
  CHECK(marvin_home_skill::degrees(-2.5) == "-2.5");
}

}  // namespace

TEST_CASE("smarthome_set: a malformed state is refused with the field named, nothing sent") {
  marvin::testing::MockRobot robot("lights", {"smarthome"});
  robot.add_device(R"({"id": "k", "name": "kitchen light", "dimmable": true})");
  const marvin_robot_api* api = robot.api();
  CHECK(api->smarthome_set(robot.host(), "k", R"({"on": 3})") == MARVIN_ERR_INVALID);
  CHECK(std::string(api->last_error(robot.host())) ==
        R"(state.on: expected "on": true|false, "brightness": 0..100 or "target_temperature": degrees Celsius, got 3)");
  CHECK(api->smarthome_set(robot.host(), "k", R"({"brightness": 101})") == MARVIN_ERR_INVALID);
  CHECK(api->smarthome_set(robot.host(), "k", "{oops") == MARVIN_ERR_INVALID);
  CHECK(std::string(api->last_error(robot.host())) == "state is not valid JSON at byte 2");
  CHECK(api->smarthome_set(robot.host(), "nothing", "on") == MARVIN_ERR_NOT_FOUND);
  CHECK(robot.actions().empty());
  CHECK(json::parse(*robot.device("k"))["on"] == false);
  CHECK(api->smarthome_set(robot.host(), "k", "on") == MARVIN_OK);
  CHECK(json::parse(*robot.device("k"))["on"] == true);
  // Without the permission: refused before anything happens.
  marvin::testing::MockRobot plain("plain", {});
  plain.add_device(R"({"id": "k", "name": "kitchen light"})");
  CHECK(plain.api()->smarthome_set(plain.host(), "k", "on") == MARVIN_ERR_PERMISSION);
  CHECK(json::parse(*plain.device("k"))["on"] == false);
}

TEST_CASE("today's templates already take most of the examples to their own intent") {
  marvin::testing::SkillHarness h(HOME_SKILL_DIR);
  std::ifstream in(std::string(HOME_SKILL_DIR) + "/skill.json");
  json manifest = json::parse(in);
  int total = 0, right = 0;
  for (const json& intent : manifest["intents"]) {
    REQUIRE(intent["examples"].size() >= 30);
    for (const json& example : intent["examples"]) {
      ++total;
      if (h.intent_of(example.get<std::string>()) == "home/" + intent["name"].get<std::string>())
        ++right;
      else
        MESSAGE("not " << intent["name"] << ": " << example);
    }
  }
  MESSAGE(right << " of " << total << " examples reach their intent");
  CHECK(right * 100 >= total * 85);
}
