#include "scripting/lua_skill.h"

#include <algorithm>
#include <stdexcept>

#include <lua.hpp>

#include "scripting/lua_json.h"
#include "scripting/skill_context.h"

namespace marvin::scripting {
namespace {

marvin_log_level to_abi(LogLevel level) {
  switch (level) {
    case LogLevel::kDebug: return MARVIN_LOG_DEBUG;
    case LogLevel::kInfo: return MARVIN_LOG_INFO;
    case LogLevel::kWarning: return MARVIN_LOG_WARNING;
    case LogLevel::kError: return MARVIN_LOG_ERROR;
  }
  return MARVIN_LOG_INFO;
}

int install_api_protected(lua_State* L) {
  install_marvin_api(L, static_cast<SkillContext*>(lua_touserdata(L, 1)));
  return 0;
}

void build(SkillContext* ctx) {
  ctx->sandbox.reset();
  ctx->handled_intents.clear();
  ctx->timers.clear();
  auto sandbox = std::make_unique<Sandbox>(ctx->spec.id, ctx->spec.folder, ctx->limits, ctx->clock);
  sandbox->set_owner(ctx);
  sandbox->set_output([ctx](LogLevel level, std::string_view text) {
    const std::string line(text);
    ctx->api->log(ctx->host, to_abi(level), line.c_str());
  });
  sandbox->set_cancel_check([ctx] {
    return ctx->api->is_cancelled != nullptr && ctx->api->is_cancelled(ctx->host) != 0;
  });
  ctx->sandbox = std::move(sandbox);
  std::string error;
  if (ctx->sandbox->protect(install_api_protected, ctx, &error) != LUA_OK) {
    throw std::runtime_error("skill '" + ctx->spec.id + "': cannot set up the Lua API: " + error);
  }
  ctx->loading = true;
  const RunResult result = ctx->sandbox->run_file(ctx->spec.entry);
  ctx->loading = false;
  if (!result.ok) throw std::runtime_error("skill '" + ctx->spec.id + "': " + result.error);
  for (const std::string& intent : ctx->declared_intents) {
    if (ctx->handled_intents.count(intent) == 0) {
      throw std::runtime_error("skill '" + ctx->spec.id + "': " + ctx->spec.entry +
                               " registers no handler for intent '" + intent +
                               "' of skill.json (add marvin.on(\"" + intent +
                               "\", function(slots) ... end))");
    }
  }
  ctx->poisoned = false;
}

// One request: a handler with its slots, or a timer.
struct Invocation {
  SkillContext* ctx;
  const char* intent;     // nullptr for a timer
  const char* utterance;
  std::int64_t timer_id;
  marvin_status status = MARVIN_OK;
  std::string error;
};

void set_error(Invocation* inv, marvin_status status, const std::string& text) noexcept {
  inv->status = status;
  try {
    inv->error = text;
  } catch (...) {
  }
}

int invoke_protected(lua_State* L) {
  auto* inv = static_cast<Invocation*>(lua_touserdata(L, 1));
  SkillContext* ctx = inv->ctx;
  Sandbox* sb = ctx->sandbox.get();
  lua_State* co = lua_newthread(L);
  int nargs = 0;
  if (inv->intent != nullptr) {
    lua_rawgetp(co, LUA_REGISTRYINDEX, &kHandlersKey);
    lua_getfield(co, -1, inv->intent);
    lua_remove(co, -2);
    push_json(co, ctx->json);
    lua_createtable(co, 0, 2);
    lua_pushstring(co, inv->intent);
    lua_setfield(co, -2, "intent");
    lua_pushstring(co, inv->utterance);
    lua_setfield(co, -2, "utterance");
    nargs = 2;
  } else {
    lua_rawgetp(co, LUA_REGISTRYINDEX, &kTimersKey);
    lua_rawgeti(co, -1, inv->timer_id);
    lua_pushnil(co);
    lua_rawseti(co, -3, inv->timer_id);
    lua_remove(co, -2);
  }
  if (!lua_isfunction(co, -1 - nargs)) {
    set_error(inv, MARVIN_ERR_INVALID, "no handler for this request");
    return 0;
  }
  ctx->handler_thread = co;
  for (;;) {
    int results = 0;
    ctx->ask_pending = false;
    sb->enter_script();
    const int status = lua_resume(co, L, nargs, &results);
    sb->leave_script();
    if (status == LUA_YIELD) {
      if (!ctx->ask_pending) {
        set_error(inv, MARVIN_ERR_INTERNAL, "coroutine.yield() called outside a coroutine");
        break;
      }
      lua_pop(co, results);
      sb->pause_clock();
      const marvin_status asked = ctx->call_text([ctx](marvin_text_out* out) {
        return ctx->api->ask(ctx->host, ctx->question.c_str(), out);
      });
      sb->resume_clock();
      if (asked != MARVIN_OK) {
        const char* reason = ctx->api->last_error(ctx->host);
        set_error(inv, asked, std::string("marvin.ask: ") +
                                  (reason != nullptr && reason[0] != '\0' ? reason : "no answer"));
        break;
      }
      lua_pushlstring(co, ctx->text.data(), ctx->text.size());
      nargs = 1;
      continue;
    }
    if (status == LUA_ERRMEM) sb->trip(std::string());
    if (status != LUA_OK) {
      marvin_status code = MARVIN_ERR_INTERNAL;
      if (sb->cancelled()) {
        code = MARVIN_ERR_CANCELLED;
      } else if (!sb->tripped() && ctx->raised_status != MARVIN_OK) {
        code = ctx->raised_status;
      }
      try {
        set_error(inv, code, sb->describe_error(co));
      } catch (...) {
        set_error(inv, code, "error");
      }
    }
    break;
  }
  ctx->handler_thread = nullptr;
  return 0;
}

marvin_status invoke(SkillContext* ctx, Invocation* inv, std::string* error) {
  if (ctx->poisoned || !ctx->sandbox) {
    try {
      ++ctx->rebuilds;
      build(ctx);
    } catch (const std::exception& e) {
      if (error != nullptr) *error = e.what();
      return MARVIN_ERR_INTERNAL;
    }
  }
  Sandbox* sb = ctx->sandbox.get();
  sb->begin_invocation();
  ctx->says = 0;
  ctx->raised_status = MARVIN_OK;
  std::string protect_error;
  const int status = sb->protect(invoke_protected, inv, &protect_error);
  if (status != LUA_OK) {
    set_error(inv, MARVIN_ERR_INTERNAL, sb->tripped() ? sb->trip_reason() : protect_error);
  }
  if (sb->tripped()) ctx->poisoned = true;
  sb->end_invocation();
  if (inv->status != MARVIN_OK) {
    const std::string message = "skill '" + ctx->spec.id + "': " + inv->error;
    ctx->api->log(ctx->host, inv->status == MARVIN_ERR_CANCELLED ? MARVIN_LOG_INFO : MARVIN_LOG_ERROR,
                  message.c_str());
    if (error != nullptr) *error = message;
  }
  return inv->status;
}

}  // namespace

LuaSkill::LuaSkill(SkillSpec spec, const marvin_robot_api* api, marvin_host* host, Limits limits,
                   Clock clock)
    : context_(std::make_unique<SkillContext>()) {
  SkillContext* ctx = context_.get();
  ctx->spec = std::move(spec);
  ctx->api = api;
  ctx->host = host;
  ctx->limits = limits;
  ctx->clock = std::move(clock);
  ctx->permissions.insert(ctx->spec.permissions.begin(), ctx->spec.permissions.end());
  ctx->permissions.insert("speech");
  ctx->declared_intents.insert(ctx->spec.intents.begin(), ctx->spec.intents.end());
  build(ctx);
}

LuaSkill::~LuaSkill() = default;

marvin_status LuaSkill::handle(const marvin_request& request, std::string* error) {
  SkillContext* ctx = context_.get();
  try {
    const char* intent = request.intent != nullptr ? request.intent : "";
    if (ctx->declared_intents.count(intent) == 0) {
      if (error != nullptr) {
        *error = "skill '" + ctx->spec.id + "': no intent '" + intent + "' in skill.json";
      }
      return MARVIN_ERR_INVALID;
    }
    const char* slots = request.slots_json != nullptr && request.slots_json[0] != '\0'
                            ? request.slots_json
                            : "{}";
    ctx->json = nlohmann::json::parse(slots, nullptr, false);
    if (ctx->json.is_discarded() || !ctx->json.is_object()) {
      if (error != nullptr) {
        *error = "skill '" + ctx->spec.id + "': slots are not a JSON object: " + slots;
      }
      return MARVIN_ERR_INVALID;
    }
    Invocation inv{ctx, intent, request.utterance != nullptr ? request.utterance : "", 0,
                   MARVIN_OK, std::string()};
    return invoke(ctx, &inv, error);
  } catch (const std::exception& e) {
    if (error != nullptr) *error = "skill '" + ctx->spec.id + "': " + e.what();
    return MARVIN_ERR_INTERNAL;
  }
}

std::optional<std::int64_t> LuaSkill::next_timer_ms() const {
  const auto& timers = context_->timers;
  if (timers.empty()) return std::nullopt;
  return std::min_element(timers.begin(), timers.end(),
                          [](const auto& a, const auto& b) { return a.due_ms < b.due_ms; })
      ->due_ms;
}

marvin_status LuaSkill::run_due_timers(std::int64_t now_unix_ms, std::string* error) {
  SkillContext* ctx = context_.get();
  marvin_status result = MARVIN_OK;
  try {
    for (;;) {
      auto& timers = ctx->timers;
      auto due = std::min_element(timers.begin(), timers.end(),
                                  [](const auto& a, const auto& b) { return a.due_ms < b.due_ms; });
      if (due == timers.end() || due->due_ms > now_unix_ms) break;
      const std::int64_t id = due->id;
      timers.erase(due);
      ctx->json = nlohmann::json::object();
      Invocation inv{ctx, nullptr, "", id, MARVIN_OK, std::string()};
      std::string message;
      const marvin_status status = invoke(ctx, &inv, &message);
      if (status != MARVIN_OK && result == MARVIN_OK) {
        result = status;
        if (error != nullptr) *error = message;
      }
    }
  } catch (const std::exception& e) {
    if (error != nullptr) *error = e.what();
    return MARVIN_ERR_INTERNAL;
  }
  return result;
}

const SkillSpec& LuaSkill::spec() const { return context_->spec; }

std::size_t LuaSkill::memory_bytes() const {
  return context_->sandbox ? context_->sandbox->memory_used() : 0;
}

int LuaSkill::rebuilds() const { return context_->rebuilds; }

}  // namespace marvin::scripting
