// The seam between the skill registry and the code that runs skills of one kind.
//
// The registry reads a skill's manifest, picks the SkillRuntime whose kind() equals the
// manifest's "kind" ("native" for shared libraries, "lua" for scripts) and asks it to load
// the skill. The runtime returns a SkillInstance; the skill manager calls handle() on it
// for each recognised request.
//
// Threading: an instance is called by one thread at a time (the host loop, or the worker
// of a long task), never concurrently. Robot API calls the skill makes during handle()
// come from that same thread.
#pragma once

#include <marvin/skill.h>

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include "skills/manifest.h"

namespace marvin::skills {

class SkillInstance {  // one loaded skill, whatever its kind; called by one thread at a time
 public:
  virtual ~SkillInstance() = default;
  // Acts on one request. On any status but MARVIN_OK, `*error` holds a sentence for the
  // log (never spoken as is). Never throws.
  virtual marvin_status handle(const marvin_request& request, std::string* error) = 0;
  // Timers the skill set (Lua's marvin.after): when the next one is due (host clock, Unix
  // ms), or nullopt. The host loop calls poll() with its clock when that time has come;
  // poll() runs what is due, from the same thread rule as handle(), and never throws.
  virtual std::optional<std::int64_t> next_timer_ms() { return std::nullopt; }
  virtual void poll(std::int64_t /*now_ms*/) {}
};

class SkillRuntime {  // loads skills of one kind ("native", "lua")
 public:
  virtual ~SkillRuntime() = default;
  virtual std::string kind() const = 0;
  // Loads the skill described by `manifest` from its folder `dir`. `api` and `host` stay
  // valid until the returned instance is destroyed. Throws std::runtime_error with a
  // message naming the skill and what is wrong (missing file, ABI mismatch, ...).
  virtual std::unique_ptr<SkillInstance> load(const Manifest& manifest,
                                              const std::filesystem::path& dir,
                                              const marvin_robot_api* api, marvin_host* host) = 0;
};

}  // namespace marvin::skills
