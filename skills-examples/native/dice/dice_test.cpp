// The dice skill's unit test: conversations with the built skill on a MockRobot.
#ifdef DICE_TEST_MAIN
#define DOCTEST_CONFIG_IMPLEMENT_WITH_MAIN
#endif
#include <doctest/doctest.h>

#include <marvin/testing/skill_harness.hpp>
#include <regex>
#include <string>
#include <vector>

using Lines = std::vector<std::string>;

TEST_CASE("one die: a number from 1 to 6, remembered for 'what did I roll'") {
  marvin::testing::SkillHarness harness(DICE_SKILL_DIR);
  CHECK(harness.say("what did I roll") == Lines{"You haven't rolled yet."});

  Lines said = harness.say("roll a die");
  REQUIRE(said.size() == 1);
  std::smatch m;
  REQUIRE(std::regex_match(said[0], m, std::regex("You rolled a ([1-6])\\.")));
  CHECK(harness.robot().stored("last_roll") == m[1].str());
  CHECK(harness.say("what did I roll last time") ==
        Lines{"Last time you rolled " + m[1].str() + "."});
}

TEST_CASE("several dice: each roll and the total, which adds up") {
  marvin::testing::SkillHarness harness(DICE_SKILL_DIR);
  Lines said = harness.say("roll 3 dice");
  REQUIRE(said.size() == 1);
  std::smatch m;
  REQUIRE(std::regex_match(
      said[0], m, std::regex("You rolled ([1-6]), ([1-6]) and ([1-6]): ([0-9]+) in total\\.")));
  CHECK(std::stoi(m[1]) + std::stoi(m[2]) + std::stoi(m[3]) == std::stoi(m[4]));
}

TEST_CASE("'roll some dice' asks how many, and re-asks once on a bad answer") {
  marvin::testing::SkillHarness harness(DICE_SKILL_DIR);
  Lines said = harness.say("roll some dice", {"two"});
  REQUIRE(said.size() == 2);
  CHECK(said[0] == "How many dice?");
  CHECK(std::regex_match(said[1], std::regex("You rolled [1-6] and [1-6]: [0-9]+ in total\\.")));

  said = harness.say("roll the dice", {"banana", "four"});
  REQUIRE(said.size() == 3);
  CHECK(said[0] == "How many dice?");
  CHECK(said[1] == "Sorry, I didn't get that. How many dice?");
  CHECK(std::regex_match(
      said[2], std::regex("You rolled [1-6], [1-6], [1-6] and [1-6]: [0-9]+ in total\\.")));

  said = harness.say("roll some dice", {"banana", "apple"});
  CHECK(said == Lines{"How many dice?", "Sorry, I didn't get that. How many dice?",
                      "Sorry, I still didn't understand. Let's leave it for now."});
  CHECK(harness.robot().answers_left() == 0);
}

TEST_CASE("more dice than it has: says its limit and rolls nothing") {
  marvin::testing::SkillHarness harness(DICE_SKILL_DIR);
  CHECK(harness.say("roll 50 dice") == Lines{"I can roll one to ten dice."});
  CHECK_FALSE(harness.robot().stored("last_roll").has_value());
}

TEST_CASE("the same clock gives the same rolls") {
  marvin::testing::SkillHarness a(DICE_SKILL_DIR);
  marvin::testing::SkillHarness b(DICE_SKILL_DIR);
  CHECK(a.say("roll 5 dice") == b.say("roll 5 dice"));
}
