// The "lua" SkillRuntime inside the skill platform (registry + manager), the test runner
// behind `marvin skill test`, and the example skills' own tests.
#include <doctest/doctest.h>

#include <cstdlib>
#include <string>

#include "scripting/lua_runtime.h"
#include "scripting/skill_tester.h"
#include "skills/manifest.h"
#include "temp_skill.h"

namespace marvin::scripting {
namespace {

using testing::TempDir;

std::filesystem::path source_dir() {
  const char* dir = std::getenv("MARVIN_SOURCE_DIR");
  REQUIRE_MESSAGE(dir != nullptr, "MARVIN_SOURCE_DIR is not set (run through ctest)");
  return dir;
}

const char* kManifest = R"({
  "id": "greeter", "name": "Greeter", "version": "1.0.0", "kind": "lua",
  "host_api": {"min": "1.0"}, "permissions": [],
  "lua": {"memory_kb": 512, "instructions": 100000},
  "intents": [{"name": "greet", "templates": ["greet {name}", "greet someone"],
               "slots": [{"name": "name", "type": "text", "required": true,
                          "question": "Whom should I greet?"}]}]
})";

TEST_CASE("the manifest's \"lua\" object lowers the budgets, never raises them") {
  const skills::Manifest manifest =
      skills::parse_manifest(nlohmann::json::parse(kManifest), "greeter/skill.json");
  Limits base;
  base.instructions = 50'000;
  const Limits limits = LuaRuntime(base).limits_for(manifest);
  CHECK(limits.memory_bytes == 512u * 1024);
  CHECK(limits.instructions == 50'000);  // the runtime's lower limit stays
  const SkillSpec spec = LuaRuntime::spec_of(manifest, "/skills/greeter");
  CHECK(spec.entry == "main.lua");
  CHECK(spec.intents == std::vector<std::string>{"greet"});
}

TEST_CASE("skill tests: passes, failures with file:line, and broken test files") {
  TempDir dir;
  dir.write("skill.json", kManifest);
  dir.write("main.lua", "marvin.on('greet', function(slots) marvin.say('Hello ' .. slots.name) end)\n");
  dir.write("tests/test_a.lua", R"(
test("greets", function()
  say("greet anna")
  expect.said("Hello anna")
end)
test("asks whom", function()
  answer("bob")
  say("greet someone")
  expect.asked("Whom should I greet?")
  expect.said("Hello bob")
end)
test("a wrong expectation", function()
  say("greet anna")
  expect.said("Good morning anna")
end)
)");
  dir.write("tests/test_b.lua", "test('x', function() end)\nthis is not lua\n");
  std::vector<std::string> lines;
  const TestReport report =
      run_skill_tests(dir.path(), [&lines](std::string_view line) { lines.emplace_back(line); });
  REQUIRE(report.tests.size() == 3);
  CHECK(report.tests[0].passed);
  CHECK(report.tests[1].passed);
  CHECK_FALSE(report.tests[2].passed);
  CHECK(report.tests[2].failure ==
        "tests/test_a.lua:14: expected Marvin to say \"Good morning anna\"; it said \"Hello anna\"");
  REQUIRE(report.errors.size() == 1);
  CHECK(report.errors[0] == "tests/test_b.lua:2: syntax error near 'is'");
  CHECK(report.passed() == 2);
  CHECK(report.failed() == 2);
  CHECK(lines.at(0) == "PASS tests/test_a.lua: greets");
}

TEST_CASE("a skill that does not load fails every test with the loader's message") {
  TempDir dir;
  dir.write("skill.json", kManifest);
  dir.write("main.lua", "marvin.on('greet', function() end)\nmarvin.say(\n");
  dir.write("tests/test_main.lua", "test('greets', function() say('greet anna') end)\n");
  const TestReport report = run_skill_tests(dir.path());
  REQUIRE(report.tests.size() == 1);
  CHECK_FALSE(report.tests[0].passed);
  CHECK(report.tests[0].failure.find("skill 'greeter': main.lua:3: unexpected symbol near <eof>") !=
        std::string::npos);
}

TEST_CASE("every example Lua skill passes its own tests") {
  const auto examples = source_dir() / "skills-examples" / "lua";
  int skills = 0;
  for (const char* name : {"hello", "medication", "where-is"}) {
    CAPTURE(std::string(name));
    std::vector<std::string> lines;
    const TestReport report = run_skill_tests(
        examples / name, [&lines](std::string_view line) { lines.emplace_back(line); });
    std::string transcript;
    for (const auto& line : lines) transcript += line + "\n";
    CHECK_MESSAGE(report.failed() == 0, transcript);
    CHECK(report.passed() >= 4);
    ++skills;
  }
  CHECK(skills == 3);
}

}  // namespace
}  // namespace marvin::scripting
