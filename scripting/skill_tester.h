// `marvin skill test DIR`: runs a Lua skill's tests (DIR/tests/*.lua) against a simulated
// robot made of the host's own parts (interpreter, skill manager with slot filling and
// confirmation, Robot API, in-memory personal data), so a test sees exactly what the robot
// would say. See sdk/lua/README.md ("Testing") for the test API:
//
//   test("greets", function()
//     say("hello marvin")                  -- one utterance, as if spoken
//     expect.said("Hello! I am Marvin.")   -- something said in that turn
//   end)
//
// Each test gets a fresh robot and a freshly loaded skill. Test files run in a sandbox
// of their own (same rules as skills). A failure reads "tests/test_main.lua:12: expected
// Marvin to say ...".
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

namespace marvin::scripting {

struct TestOutcome {
  std::string file;     // "tests/test_main.lua"
  std::string name;     // as given to test()
  bool passed = false;
  std::string failure;  // "tests/test_main.lua:12: expected ..."
  std::vector<std::string> log;  // the skill's log during the test (shown on failure)
};

struct TestReport {
  std::vector<TestOutcome> tests;
  std::vector<std::string> errors;  // files that did not load, the skill not loading, ...
  int passed() const;
  int failed() const;  // failed tests + errors
};

// Runs every tests/*.lua of the skill in `skill_dir` (in name order). `progress`, when
// set, receives one line per test as it finishes. Never throws for a skill's mistakes.
TestReport run_skill_tests(const std::filesystem::path& skill_dir,
                           const std::function<void(std::string_view)>& progress = {});

}  // namespace marvin::scripting
