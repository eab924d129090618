// marvin::testing::SkillHarness: a skill's unit test as a conversation.
//
// The harness loads one skill the way the robot does (its skill.json, then its library,
// or a descriptor compiled into the test), sends utterances through the robot's own
// interpreter and skill manager (slot filling, confirmation, apologies included), and
// answers questions from a script. Everything runs on the test's thread, long intents
// too: there is nothing to wait for.
//
//   marvin::testing::SkillHarness harness(DICE_SKILL_DIR);
//   auto said = harness.say("roll some dice", {"three"});
//   CHECK(said.at(0) == "How many dice?");
//   CHECK(harness.robot().said().back().rfind("You rolled", 0) == 0);
//
// Link MarvinSDK::testing.
#ifndef MARVIN_TESTING_SKILL_HARNESS_HPP_
#define MARVIN_TESTING_SKILL_HARNESS_HPP_

#include <filesystem>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "marvin/skill.h"
#include "marvin/testing/mock_robot.hpp"

namespace marvin::testing {

class SkillHarness {
 public:
  // Loads the skill in folder `skill_dir` (skill.json and the library it names) with the
  // permissions of its manifest. Throws std::runtime_error with the robot's message if the
  // skill would not load (bad manifest, ABI mismatch, ...).
  explicit SkillHarness(const std::filesystem::path& skill_dir);
  // A skill compiled into the test: its manifest file and marvin::skill_descriptor<S>(id).
  SkillHarness(const std::filesystem::path& manifest_file,
               const marvin_skill_descriptor* descriptor);
  ~SkillHarness();
  SkillHarness(const SkillHarness&) = delete;
  SkillHarness& operator=(const SkillHarness&) = delete;

  // The robot the skill acts on: set the clock and contacts, inspect said() and actions().
  MockRobot& robot();

  // Says `utterance` to the robot; `answers` answer its questions in order (slot filling,
  // confirmation, the skill's own ask()). Returns what the robot said during this turn.
  std::vector<std::string> say(std::string_view utterance, std::vector<std::string> answers = {});

  // "skill/intent" the utterance is recognised as, or "" when nothing matches.
  std::string intent_of(std::string_view utterance) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace marvin::testing

#endif  // MARVIN_TESTING_SKILL_HARNESS_HPP_
