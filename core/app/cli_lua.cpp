// The Lua skill author's tools:
//   marvin skill new NAME    scaffold a Lua skill (skill.json, main.lua, tests/test_main.lua)
//   marvin skill test DIR    run DIR/tests/*.lua against the simulated robot
//   marvin skill run DIR     talk to the skill in DIR in the simulated robot console
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <regex>
#include <string>
#include <thread>

#include "app/cli.h"
#include "app/host.h"
#include "common/log.h"
#include "scripting/lua_runtime.h"
#include "scripting/skill_tester.h"
#include "skills/api_json.h"

namespace marvin::app {
namespace {

namespace fs = std::filesystem;

std::string replace_all(std::string text, const std::string& from, const std::string& to) {
  for (std::size_t at = text.find(from); at != std::string::npos; at = text.find(from, at + to.size())) {
    text.replace(at, from.size(), to);
  }
  return text;
}

const char* kManifest = R"({
  "id": "@ID@",
  "name": "@TITLE@",
  "version": "0.1.0",
  "kind": "lua",
  "host_api": {"min": "1.0"},
  "permissions": ["storage"],
  "intents": [
    {
      "name": "hello",
      "templates": ["(hello|hi) @WORDS@", "say hello to {name}"],
      "slots": [{"name": "name", "type": "text"}]
    }
  ]
}
)";

const char* kMain = R"(-- @TITLE@: a Lua skill for Marvin. The API is described in sdk/lua/README.md.
--
-- Each intent of skill.json gets a handler: marvin.on("intent", function(slots) ... end).
-- `slots` holds what the user said for the intent's {slots}.

marvin.on("hello", function(slots)
  local times = tonumber(marvin.storage.get("times") or "0") + 1
  marvin.storage.set("times", times)
  if slots.name then
    marvin.say("Hello " .. slots.name .. "!")
  else
    marvin.say("Hello! You greeted me " .. times .. " times.")
  end
end)
)";

const char* kTest = R"(-- Run with: marvin skill test <this skill's folder>

test("greets and counts", function()
  say("hello @WORDS@")
  expect.said("Hello! You greeted me 1 times.")
  say("hi @WORDS@")
  expect.said("Hello! You greeted me 2 times.")
  expect.stored("times", "2")
end)

test("greets someone by name", function()
  say("say hello to grandma")
  expect.said("Hello grandma!")
end)
)";

void new_skill(const std::string& name, const std::string& parent) {
  static const std::regex valid("[a-z0-9][a-z0-9_-]*");
  if (!std::regex_match(name, valid)) {
    throw CliError("skill names are lower-case letters, digits, '-' and '_' (got \"" + name + "\")", 2);
  }
  const fs::path dir = fs::path(parent) / name;
  if (fs::exists(dir)) throw CliError(dir.string() + " already exists; choose another name", 1);
  const std::string title = replace_all(replace_all(name, "-", " "), "_", " ");
  const auto fill = [&](const char* text) {
    return replace_all(replace_all(replace_all(text, "@ID@", name), "@TITLE@", title), "@WORDS@",
                       title);
  };
  fs::create_directories(dir / "tests");
  const std::pair<const char*, const char*> files[] = {
      {"skill.json", kManifest}, {"main.lua", kMain}, {"tests/test_main.lua", kTest}};
  for (const auto& [file, text] : files) {
    std::ofstream out(dir / file, std::ios::binary);
    out << fill(text);
    if (!out) throw CliError("cannot write " + (dir / file).string(), 1);
    write_line("created " + (dir / file).string());
  }
  write_line("Try it: marvin skill test " + dir.string() + "   or   marvin skill run " +
             dir.string());
}

void test_skill(const std::string& dir) {
  if (!fs::is_regular_file(fs::path(dir) / "skill.json")) {
    throw CliError(dir + ": no skill.json (give the skill's folder)", 2);
  }
  set_log_level(LogLevel::kInfo);
  const scripting::TestReport report = scripting::run_skill_tests(dir, write_line);
  for (const auto& error : report.errors) {
    if (error.find("no *.lua test files") != std::string::npos) write_line(error);
  }
  write_line(std::to_string(report.passed()) + " passed, " + std::to_string(report.failed()) +
             " failed");
  if (report.failed() > 0) throw CliError("some tests failed", 1);
}

struct RunSkillOptions {
  std::string dir;
  std::string time_zone;
  std::string clock;
  bool builtin = false;
};

void run_skill(const RunSkillOptions& o) {
  set_log_level(LogLevel::kWarning);
  HostOptions options;
  options.builtin_skills = o.builtin;
  options.time_zone = o.time_zone.empty() ? system_time_zone() : o.time_zone;
  if (!o.clock.empty()) {
    try {
      options.fixed_now_ms = skills::local_to_utc_ms(o.clock, options.time_zone);
    } catch (const std::exception& e) {
      throw CliError(std::string("--clock: ") + e.what(), 2);
    }
  }
  Host host(options, write_line);
  host.add_runtime(std::make_unique<scripting::LuaRuntime>());
  host.load();
  if (!host.registry().load_skill(o.dir)) {
    throw CliError(host.registry().errors().back().message, 1);
  }
  const auto& skill = host.registry().skills().back();
  const bool interactive = isatty(STDIN_FILENO) != 0;
  if (interactive) {
    write_line("Skill '" + skill->manifest.id + "' loaded. Type a request; Ctrl-D quits.");
    for (const auto& intent : skill->manifest.intents) {
      if (!intent.templates.empty()) write_line("  e.g. \"" + intent.templates.front() + "\"");
    }
  } else {
    host.loop().on_heard([](std::string_view line) { write_line("You: " + std::string(line)); });
  }
  ConsoleReader reader(host);
  host.body().set_light(devices::Light::kAwaiting);
  host.loop().run();
}

void install_lua_commands(CLI::App& root) {
  CLI::App& skill = command_group(root, "skill", "Write, test and manage skills");

  static std::string name;
  static std::string parent = ".";
  CLI::App* create = skill.add_subcommand("new", "Create a Lua skill: skill.json, main.lua, a test");
  create->add_option("name", name, "The skill's id, e.g. plant-care")->required();
  create->add_option("--dir", parent, "Where to create the skill's folder (default: here)");
  create->callback([] { new_skill(name, parent); });

  static std::string test_dir;
  CLI::App* test = skill.add_subcommand("test", "Run a Lua skill's tests/*.lua against the simulated robot");
  test->add_option("dir", test_dir, "The skill's folder")->required();
  test->callback([] { test_skill(test_dir); });

  static RunSkillOptions run_options;
  CLI::App* run = skill.add_subcommand("run", "Talk to one skill in the simulated robot console");
  run->add_option("dir", run_options.dir, "The skill's folder")->required();
  run->add_option("--time-zone", run_options.time_zone, "IANA time zone (default: the system's)");
  run->add_option("--clock", run_options.clock, "A stopped clock, local time YYYY-MM-DDTHH:MM");
  run->add_flag("--with-builtin", run_options.builtin, "Also load the built-in skills");
  run->callback([] { run_skill(run_options); });
}

MARVIN_CLI_COMMANDS(install_lua_commands);

}  // namespace
}  // namespace marvin::app
