// One loaded Lua skill: its sandbox, the `marvin` API bound to the Robot API, and the
// handlers the script registered for its intents.
//
// Life cycle: the constructor builds the sandbox and runs the entry file (main.lua), which
// registers one handler per intent of skill.json with marvin.on(). handle() runs the
// intent's handler in a fresh coroutine under a fresh budget (see sandbox.h). When the
// handler calls marvin.ask(), the coroutine yields to handle(), which calls the Robot API's
// ask() (blocking the calling thread, never the Lua state's budget: the clock is paused)
// and resumes the handler with the answer.
//
// After a budget trip the state is discarded and rebuilt from the entry file before the
// next request, so a runaway request cannot leave the skill half-updated; global variables
// of the script start afresh then (persistent data belongs in marvin.storage).
//
// Errors the skill author can cause read "skill 'ID': main.lua:LINE: message"; they are
// returned by handle() and written to the skill's log (Robot API log()).
//
// Threading: one thread at a time (the skill manager's rule for every SkillInstance).
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <marvin/skill.h>

#include "scripting/sandbox.h"

namespace marvin::scripting {

// What the runtime needs to know about a skill (the manifest, reduced).
struct SkillSpec {
  std::string id;
  std::filesystem::path folder;
  std::string entry = "main.lua";
  std::vector<std::string> intents;      // declared in skill.json
  std::vector<std::string> permissions;  // granted ("speech" is implicit)
};

struct SkillContext;

class LuaSkill {
 public:
  // Loads the skill. `api` and `host` must outlive the LuaSkill. Throws std::runtime_error
  // ("skill 'ID': main.lua:3: ...") when the script does not load or leaves a declared
  // intent without a handler.
  LuaSkill(SkillSpec spec, const marvin_robot_api* api, marvin_host* host, Limits limits = {},
           Clock clock = {});
  ~LuaSkill();
  LuaSkill(const LuaSkill&) = delete;
  LuaSkill& operator=(const LuaSkill&) = delete;

  // Runs the handler of request.intent with the request's slots. MARVIN_OK on success;
  // otherwise *error holds the sentence for the log. Never throws.
  marvin_status handle(const marvin_request& request, std::string* error);

  // marvin.after(seconds, fn) timers: when the next one is due (host clock, Unix ms), and
  // running every timer due at `now_unix_ms` (each as its own request, budgets included).
  // The host calls run_due_timers() from the thread that calls handle().
  std::optional<std::int64_t> next_timer_ms() const;
  marvin_status run_due_timers(std::int64_t now_unix_ms, std::string* error);

  const SkillSpec& spec() const;
  // Bytes held by the Lua state.
  std::size_t memory_bytes() const;
  // How often the state was rebuilt after a budget trip.
  int rebuilds() const;

 private:
  std::unique_ptr<SkillContext> context_;
};

}  // namespace marvin::scripting
