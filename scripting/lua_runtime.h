// The SkillRuntime of kind "lua": loads a Lua skill (skill.json + main.lua) into its own
// sandbox (see lua_skill.h and sandbox.h).
//
// The host registers it once before loading skills:
//
//   registry.add_runtime(std::make_unique<marvin::scripting::LuaRuntime>());
//   // or, with the app's wiring: host.add_runtime(std::make_unique<LuaRuntime>());
//
// Budgets come from LuaRuntime's Limits; a manifest may lower (never raise) them with an
// optional "lua" object: {"memory_kb": 1024, "instructions": 1000000, "time_ms": 500}.
#pragma once

#include <memory>
#include <string>

#include "scripting/lua_skill.h"
#include "skills/skill_runtime.h"

namespace marvin::scripting {

// A loaded Lua skill as the skill manager sees it.
class LuaSkillInstance : public skills::SkillInstance {
 public:
  explicit LuaSkillInstance(std::unique_ptr<LuaSkill> skill) : skill_(std::move(skill)) {}
  marvin_status handle(const marvin_request& request, std::string* error) override {
    return skill_->handle(request, error);
  }
  // marvin.after timers, for the host loop.
  std::optional<std::int64_t> next_timer_ms() override { return skill_->next_timer_ms(); }
  void poll(std::int64_t now_ms) override;
  // For the test runner.
  LuaSkill& skill() { return *skill_; }

 private:
  std::unique_ptr<LuaSkill> skill_;
};

class LuaRuntime : public skills::SkillRuntime {
 public:
  explicit LuaRuntime(Limits limits = {}, Clock clock = {})
      : limits_(limits), clock_(std::move(clock)) {}
  std::string kind() const override { return "lua"; }
  // Throws std::runtime_error "skill 'ID': main.lua:LINE: message" when the script does
  // not load.
  std::unique_ptr<skills::SkillInstance> load(const skills::Manifest& manifest,
                                              const std::filesystem::path& dir,
                                              const marvin_robot_api* api,
                                              marvin_host* host) override;

  // The SkillSpec and Limits for a manifest (exposed for tests and the benchmark).
  static SkillSpec spec_of(const skills::Manifest& manifest, const std::filesystem::path& dir);
  Limits limits_for(const skills::Manifest& manifest) const;

 private:
  Limits limits_;
  Clock clock_;
};

}  // namespace marvin::scripting
