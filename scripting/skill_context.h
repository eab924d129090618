// Internal to scripting/: the state LuaSkill and the `marvin` API bindings share.
//
// Lua C functions reach it through Sandbox::owner(). Text and JSON the bindings compute in
// C++ live in the scratch members here, never in locals of a function that may raise a
// Lua error (see sandbox.cpp).
#pragma once

#include <cstdint>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include <marvin/robot.h>
#include <nlohmann/json.hpp>

#include "scripting/lua_skill.h"
#include "scripting/sandbox.h"

namespace marvin::scripting {

// Registry keys of the skill's tables.
extern char kHandlersKey;  // intent name -> handler function
extern char kTimersKey;    // timer id -> function

// How many marvin.say() one request may make: a loop of says is a bug, not a speech.
inline constexpr int kMaxSaysPerRequest = 20;
inline constexpr std::size_t kMaxSayBytes = 2000;
inline constexpr std::size_t kMaxPendingTimers = 32;

struct SkillContext {
  SkillSpec spec;
  const marvin_robot_api* api = nullptr;
  marvin_host* host = nullptr;
  Limits limits;
  Clock clock;
  std::unique_ptr<Sandbox> sandbox;
  std::set<std::string> permissions;
  std::set<std::string> declared_intents;
  std::set<std::string> handled_intents;
  bool poisoned = false;  // a budget tripped: rebuild before the next request
  int rebuilds = 0;

  // During one request.
  bool loading = false;
  lua_State* handler_thread = nullptr;
  bool ask_pending = false;
  int says = 0;
  marvin_status raised_status = MARVIN_OK;  // set when a binding raises for an API status

  struct Timer {
    std::int64_t id;
    std::int64_t due_ms;
  };
  std::vector<Timer> timers;
  std::int64_t next_timer_id = 1;

  // Scratch (see the file comment).
  std::string question;
  std::string answer;
  std::string text;
  std::string message;
  nlohmann::json json;
  nlohmann::json guide_event;  // the event marvin.guide_to's on_event is called with
  bool guide_failed = false;   // on_event raised an error (its sentence in message)

  static SkillContext* from(lua_State* L) {
    return static_cast<SkillContext*>(Sandbox::from(L)->owner());
  }

  // Calls `call(out)` with a growing text buffer until the text fits; leaves it in `text`.
  // Retrying an acting call (look_around, ask, ...) does not act twice: the host keeps the
  // answer that did not fit for the retry (marvin/abi.h, marvin_text_out).
  template <typename Call>
  marvin_status call_text(Call call) noexcept {
    try {
      if (text.capacity() < 256) text.reserve(256);
      for (int attempt = 0; attempt < 3; ++attempt) {
        text.resize(text.capacity());
        marvin_text_out out{text.data(), text.size() + 1, 0};
        const marvin_status status = call(&out);
        if (status == MARVIN_ERR_TRUNCATED && out.length + 1 > out.capacity) {
          text.reserve(out.length + 1);
          continue;
        }
        text.resize(status == MARVIN_OK ? std::min(out.length, text.size()) : 0);
        return status;
      }
      return MARVIN_ERR_INTERNAL;
    } catch (...) {
      return MARVIN_ERR_INTERNAL;
    }
  }
};

// Builds the `marvin` table for `ctx` and makes it a protected global. Runs in protected
// mode (Sandbox::protect).
void install_marvin_api(lua_State* L, SkillContext* ctx);

}  // namespace marvin::scripting
