// The navigation skill against the mock robot's scripted going places.
#include <doctest/doctest.h>

#include <algorithm>
#include <marvin/testing/mock_robot.hpp>
#include <marvin/testing/skill_harness.hpp>
#include <string>

using marvin::testing::SkillHarness;

TEST_CASE("go to the kitchen: the robot goes and says where it is") {
  SkillHarness h(NAVIGATION_SKILL_DIR);
  h.robot().add_place("kitchen", "kitchen");
  auto said = h.say("go to the kitchen");
  CHECK(said == std::vector<std::string>{"On my way to the kitchen.", "I'm in the kitchen."});
  const auto& actions = h.robot().actions();
  CHECK(std::find(actions.begin(), actions.end(), "go_to kitchen") != actions.end());
  CHECK(h.robot().room() == "kitchen");
  CHECK(h.say("where are you") == std::vector<std::string>{"I'm in the kitchen."});
}

TEST_CASE("a place in a room, come here, and places the robot does not know") {
  SkillHarness h(NAVIGATION_SKILL_DIR);
  h.robot().add_place("the sofa", "living room");
  h.robot().add_place("me", "living room");
  CHECK(h.say("go to the sofa").back() == "I'm at the sofa, in the living room.");
  h.robot().set_room("hall");
  CHECK(h.say("come here").back() == "I'm here.");
  CHECK(h.robot().room() == "living room");
  // An unknown place: said at once, and the robot does not set off.
  CHECK(h.say("go to the garage") ==
        std::vector<std::string>{"Sorry, I don't know where the garage is."});
  CHECK(h.say("go to the charger") ==
        std::vector<std::string>{"Sorry, I don't know where the charger is."});
  CHECK(h.robot().room() == "living room");
  CHECK(h.say("go to my sofa").front() == "On my way to the sofa.");
}

TEST_CASE("how far: metres along the robot's path, rounded as people say them") {
  SkillHarness h(NAVIGATION_SKILL_DIR);
  h.robot().add_place("kitchen", "kitchen");
  h.robot().add_place("the bed", "bedroom");
  h.robot().add_place("the front door", "hall");
  h.robot().add_place("Anna", "living room");
  h.robot().add_place("hall", "hall");
  h.robot().add_place("bathroom", "bathroom");
  h.robot().set_path_length("kitchen", 3.3);
  h.robot().set_path_length("the bed", 6.6);
  h.robot().set_path_length("the front door", 0.6);
  h.robot().set_path_length("Anna", 1.2);
  h.robot().set_room("hall");
  CHECK(h.intent_of("how far is the kitchen") == "navigation/how_far");
  CHECK(h.say("how far is the kitchen") ==
        std::vector<std::string>{"The kitchen is about 3 metres away."});
  // "the bed" is the furniture here, not bedtime.
  CHECK(h.say("is the bed far from here") ==
        std::vector<std::string>{"The bed is about 7 metres away."});
  CHECK(h.say("how far away is the front door") ==
        std::vector<std::string>{"The front door is less than a metre away."});
  CHECK(h.say("how far is Anna") ==
        std::vector<std::string>{"The last place I saw Anna is about a metre away."});
  CHECK(h.say("how far is the hall") == std::vector<std::string>{"I'm in the hall now."});
  // On the map, but no path length (no way there now, or the robot is driving).
  CHECK(h.say("how far is the bathroom") ==
        std::vector<std::string>{"Sorry, I can't tell how far the bathroom is from here."});
  CHECK(h.say("how far is the garage") ==
        std::vector<std::string>{"Sorry, I don't know where the garage is."});
  // Asking moves nothing.
  CHECK(h.robot().room() == "hall");
  const auto& actions = h.robot().actions();
  CHECK(std::none_of(actions.begin(), actions.end(),
                     [](const std::string& a) { return a.rfind("go_to", 0) == 0; }));
}

TEST_CASE("go to sleep: back to the charger when the map has one, else rest where it is") {
  SkillHarness h(NAVIGATION_SKILL_DIR);
  const std::vector<std::string> at_rest = {"OK. Say \"Marvin\" when you need me."};
  h.robot().add_place("kitchen", "kitchen");
  h.robot().set_room("kitchen");
  CHECK(h.say("go to sleep") == at_rest);
  CHECK(h.robot().room() == "kitchen");
  h.robot().add_place("the charger", "hall");
  for (const char* said : {"go to sleep", "go back to your charger", "you can go now",
                           "go to bed", "go home"}) {
    CAPTURE(said);
    h.robot().set_room("kitchen");
    CHECK(h.intent_of(said) == "navigation/rest");
    CHECK(h.say(said) ==
          std::vector<std::string>{"On my way to the charger.",
                                   "I'm at my charger. Say \"Marvin\" when you need me."});
    CHECK(h.robot().room() == "hall");
  }
  // "the bed" is a place to go to, not bedtime.
  CHECK(h.intent_of("go to the bed") == "navigation/go_to");
}

TEST_CASE("come here without knowing where the user is") {
  SkillHarness h(NAVIGATION_SKILL_DIR);
  CHECK(h.say("come here").back() == "Sorry, I don't know where you are.");
  CHECK(h.say("where am i") == std::vector<std::string>{"Sorry, I don't know where you are."});
}

TEST_CASE("where am I: the room the map places the user in, not the robot's") {
  SkillHarness h(NAVIGATION_SKILL_DIR);
  h.robot().add_place("me", "bedroom");
  h.robot().set_room("hall");
  CHECK(h.intent_of("where am I") == "navigation/where_am_i");
  CHECK(h.say("where am I") == std::vector<std::string>{"You're in the bedroom."});
  CHECK(h.say("which room am I in") == std::vector<std::string>{"You're in the bedroom."});
  CHECK(h.say("where are you") == std::vector<std::string>{"I'm in the hall."});
}

TEST_CASE("a blocked way is explained") {
  SkillHarness h(NAVIGATION_SKILL_DIR);
  h.robot().add_place("kitchen", "kitchen");
  h.robot().block_place("kitchen", "the kitchen door is blocked");
  CHECK(h.say("go to the kitchen").back() ==
        "Sorry, I can't get to the kitchen: the kitchen door is blocked.");
  CHECK(h.robot().room() == "hall");
}

TEST_CASE("between rooms") {
  SkillHarness h(NAVIGATION_SKILL_DIR);
  h.robot().set_room("");
  CHECK(h.say("where are you") == std::vector<std::string>{"I'm in a doorway, between two rooms."});
}

TEST_CASE("the Robot API checks the permission before going anywhere") {
  marvin::testing::MockRobot robot("nomotion", {});
  robot.add_place("kitchen", "kitchen");
  CHECK(robot.api()->go_to(robot.host(), "kitchen") == MARVIN_ERR_PERMISSION);
  CHECK(std::string(robot.api()->last_error(robot.host())) ==
        "permission 'motion' is not granted to skill 'nomotion'");
  CHECK(robot.room() == "hall");
  CHECK(robot.actions().empty());
  marvin_text_out out{nullptr, 0, 0};
  CHECK(robot.api()->where_am_i(robot.host(), &out) == MARVIN_ERR_PERMISSION);
  CHECK(robot.api()->minor >= 2);
}

TEST_CASE("a person is named as the map spells them, without \"the\" (API 1.3 place_find)") {
  SkillHarness h(NAVIGATION_SKILL_DIR);
  h.robot().add_place("Anna", "living room");
  const auto said = h.say("go to anna");
  REQUIRE(said.size() == 2);
  CHECK(said[0] == "On my way to Anna.");
  CHECK(said[1] == "I'm at Anna, in the living room.");
}

TEST_CASE("turn left, a little to the right, around: said, then turned (counter-clockwise +)") {
  SkillHarness h(NAVIGATION_SKILL_DIR);
  struct Case {
    const char* said;
    const char* answer;
    const char* action;
  };
  const Case cases[] = {
      {"turn left", "Turning to the left.", "turn 90"},
      {"turn to your right", "Turning to the right.", "turn -90"},
      {"turn a little to the left", "Turning a little to the left.", "turn 30"},
      {"turn around", "Turning around.", "turn 180"},
      {"face the other way", "Turning around.", "turn 180"},
  };
  for (const Case& c : cases) {
    CAPTURE(c.said);
    h.robot().clear();
    CHECK(h.intent_of(c.said) == "navigation/turn");
    CHECK(h.say(c.said) == std::vector<std::string>{c.answer});
    std::vector<std::string> moved;  // the status light's changes left out
    for (const std::string& a : h.robot().actions()) {
      if (a.rfind("light", 0) != 0) moved.push_back(a);
    }
    INFO(moved.size());
    CHECK(moved == std::vector<std::string>{c.action});
  }
}
