// The `marvin` table a Lua skill sees: the Robot API, with the skill's permissions.
//
// Every function checks its permission before calling the host (which checks again), so
// a skill learns at the line of its call what it lacks. API failures raise
// "marvin.NAME: <the host's sentence>". See sdk/lua/README.md for the user's view.
//
// No C++ object with a destructor is alive across a call that may raise (Lua errors
// longjmp): computed text goes through SkillContext's scratch members.
#include <cmath>
#include <cstddef>
#include <cstring>
#include <initializer_list>

#include <lua.hpp>

#include <cstddef>

#include "scripting/lua_json.h"
#include "scripting/skill_context.h"

namespace marvin::scripting {

char kHandlersKey;
char kTimersKey;

namespace {

constexpr std::int64_t kDefaultListDays = 7;

[[noreturn]] void raise_status(lua_State* L, SkillContext* ctx, const char* what,
                               marvin_status status) {
  ctx->raised_status = status;
  const char* reason = ctx->api->last_error(ctx->host);
  if (reason == nullptr || reason[0] == '\0') {
    switch (status) {
      case MARVIN_ERR_PERMISSION: reason = "permission denied"; break;
      case MARVIN_ERR_UNAVAILABLE: reason = "not available on this robot"; break;
      case MARVIN_ERR_INVALID: reason = "invalid argument"; break;
      case MARVIN_ERR_NOT_FOUND: reason = "not found"; break;
      case MARVIN_ERR_CANCELLED: reason = "cancelled"; break;
      default: reason = "the robot could not do it"; break;
    }
  }
  luaL_error(L, "marvin.%s: %s", what, reason);
  std::abort();
}

void require_permission(lua_State* L, SkillContext* ctx, const char* permission,
                        const char* what) {
  // std::set::count with a const char* builds a temporary string: keep it out of the
  // frame that raises.
  bool granted = false;
  try {
    granted = ctx->permissions.count(permission) != 0;
  } catch (...) {
  }
  if (granted) return;
  ctx->raised_status = MARVIN_ERR_PERMISSION;
  luaL_error(L, "marvin.%s: permission '%s' is not granted to skill '%s' (add \"%s\" to "
             "\"permissions\" in skill.json)", what, permission, ctx->spec.id.c_str(), permission);
}

// Hosts built against an older minor of the Robot API may leave newer slots empty.
void need(lua_State* L, SkillContext* ctx, bool present, const char* what) {
  if (present) return;
  ctx->raised_status = MARVIN_ERR_UNAVAILABLE;
  luaL_error(L, "marvin.%s: not available on this robot", what);
}

void check(lua_State* L, SkillContext* ctx, const char* what, marvin_status status) {
  if (status != MARVIN_OK) raise_status(L, ctx, what, status);
}

// Pushes ctx->json (parsed from ctx->text) or raises.
void push_json_text(lua_State* L, SkillContext* ctx, const char* what) {
  bool ok = true;
  try {
    ctx->json = nlohmann::json::parse(ctx->text);
  } catch (...) {
    ok = false;
  }
  if (!ok) luaL_error(L, "marvin.%s: the robot answered with invalid JSON", what);
  push_json(L, ctx->json);
}

// Converts the table argument at `index` into ctx->text (JSON) or raises.
void table_to_json_text(lua_State* L, SkillContext* ctx, int index, const char* what) {
  luaL_checktype(L, index, LUA_TTABLE);
  bool ok = false;
  try {
    ok = to_json(L, index, &ctx->json, &ctx->message);
    if (ok) ctx->text = ctx->json.dump();
  } catch (...) {
    ok = false;
    ctx->message = "cannot convert the table to JSON";
  }
  if (!ok) luaL_error(L, "marvin.%s: %s", what, ctx->message.c_str());
}

// --- intents and timers ------------------------------------------------------------------

int l_on(lua_State* L) {
  SkillContext* ctx = SkillContext::from(L);
  const char* intent = luaL_checkstring(L, 1);
  luaL_checktype(L, 2, LUA_TFUNCTION);
  if (!ctx->loading) {
    return luaL_error(L, "marvin.on: handlers are registered while the skill loads (at the top "
                      "level of %s)", ctx->spec.entry.c_str());
  }
  bool declared = false;
  try {
    declared = ctx->declared_intents.count(intent) != 0;
    if (declared) ctx->handled_intents.insert(intent);
    if (!declared) {
      ctx->message.clear();
      for (const std::string& name : ctx->declared_intents) {
        if (!ctx->message.empty()) ctx->message += ", ";
        ctx->message += name;
      }
    }
  } catch (...) {
  }
  if (!declared) {
    return luaL_error(L, "marvin.on: intent '%s' is not declared in skill.json (declared: %s)",
                      intent, ctx->message.empty() ? "none" : ctx->message.c_str());
  }
  lua_rawgetp(L, LUA_REGISTRYINDEX, &kHandlersKey);
  lua_pushvalue(L, 1);
  lua_pushvalue(L, 2);
  lua_rawset(L, -3);
  return 0;
}

int l_after(lua_State* L) {
  SkillContext* ctx = SkillContext::from(L);
  const lua_Number seconds = luaL_checknumber(L, 1);
  luaL_checktype(L, 2, LUA_TFUNCTION);
  if (!(seconds >= 0 && seconds <= 7 * 24 * 3600.0)) {
    return luaL_error(L, "marvin.after: seconds must be between 0 and one week (use "
                      "marvin.schedule for reminders)");
  }
  if (ctx->timers.size() >= kMaxPendingTimers) {
    return luaL_error(L, "marvin.after: too many pending timers (at most %d)",
                      static_cast<int>(kMaxPendingTimers));
  }
  std::int64_t now = 0;
  need(L, ctx, ctx->api->now != nullptr, "after");
  check(L, ctx, "after", ctx->api->now(ctx->host, &now));
  const std::int64_t id = ctx->next_timer_id++;
  lua_rawgetp(L, LUA_REGISTRYINDEX, &kTimersKey);
  lua_pushvalue(L, 2);
  lua_rawseti(L, -2, id);
  bool ok = true;
  try {
    ctx->timers.push_back({id, now + static_cast<std::int64_t>(std::llround(seconds * 1000.0))});
  } catch (...) {
    ok = false;
  }
  if (!ok) return luaL_error(L, "marvin.after: out of memory");
  lua_pushinteger(L, id);
  return 1;
}

// --- speech --------------------------------------------------------------------------------

int l_say(lua_State* L) {
  SkillContext* ctx = SkillContext::from(L);
  std::size_t len = 0;
  const char* text = luaL_checklstring(L, 1, &len);
  if (len > kMaxSayBytes) {
    return luaL_error(L, "marvin.say: the sentence is %d bytes long (at most %d)",
                      static_cast<int>(len), static_cast<int>(kMaxSayBytes));
  }
  if (++ctx->says > kMaxSaysPerRequest) {
    return luaL_error(L, "marvin.say: more than %d sentences in one request", kMaxSaysPerRequest);
  }
  check(L, ctx, "say", ctx->api->say(ctx->host, text));
  return 0;
}

int ask_continue(lua_State*, int, lua_KContext) {
  return 1;  // the answer handle() pushed when resuming
}

// Asks from inside a coroutine the skill made (or where yielding is impossible): calls the
// host directly, with the clock paused.
int ask_now(lua_State* L, SkillContext* ctx) {
  Sandbox* sb = ctx->sandbox.get();
  sb->pause_clock();
  const marvin_status status = ctx->call_text([ctx](marvin_text_out* out) {
    return ctx->api->ask(ctx->host, ctx->question.c_str(), out);
  });
  sb->resume_clock();
  check(L, ctx, "ask", status);
  lua_pushlstring(L, ctx->text.data(), ctx->text.size());
  return 1;
}

int l_ask(lua_State* L) {
  SkillContext* ctx = SkillContext::from(L);
  std::size_t len = 0;
  const char* question = luaL_checklstring(L, 1, &len);
  if (len > kMaxSayBytes) return luaL_error(L, "marvin.ask: the question is too long");
  if (ctx->loading || ctx->handler_thread == nullptr) {
    return luaL_error(L, "marvin.ask: questions are asked from an intent handler or a timer, "
                      "not while the skill loads");
  }
  bool ok = true;
  try {
    ctx->question.assign(question, len);
  } catch (...) {
    ok = false;
  }
  if (!ok) return luaL_error(L, "marvin.ask: out of memory");
  if (L == ctx->handler_thread && lua_isyieldable(L)) {
    ctx->ask_pending = true;
    return lua_yieldk(L, 0, 0, ask_continue);
  }
  return ask_now(L, ctx);
}

// --- body ------------------------------------------------------------------------------------

int l_light(lua_State* L) {
  SkillContext* ctx = SkillContext::from(L);
  static const char* const names[] = {"off", "awaiting", "listening", "executing", nullptr};
  const int light = luaL_checkoption(L, 1, nullptr, names);
  require_permission(L, ctx, "light", "light");
  need(L, ctx, ctx->api->set_light != nullptr, "light");
  check(L, ctx, "light", ctx->api->set_light(ctx->host, static_cast<marvin_light>(light)));
  return 0;
}

int l_move(lua_State* L) {
  SkillContext* ctx = SkillContext::from(L);
  static const char* const names[] = {"forward", "backward", "left", "right", nullptr};
  const int direction = luaL_checkoption(L, 1, nullptr, names);
  const lua_Number seconds = luaL_checknumber(L, 2);
  const lua_Integer speed = luaL_optinteger(L, 3, 128);
  luaL_argcheck(L, seconds > 0 && seconds <= 30, 2, "seconds must be in (0, 30]");
  luaL_argcheck(L, speed >= 0 && speed <= 255, 3, "speed must be 0..255");
  require_permission(L, ctx, "motion", "move");
  need(L, ctx, ctx->api->move != nullptr, "move");
  Sandbox* sb = ctx->sandbox.get();
  sb->pause_clock();  // the body's time is not the script's
  const marvin_status status =
      ctx->api->move(ctx->host, static_cast<marvin_direction>(direction),
                     static_cast<std::uint8_t>(speed),
                     static_cast<std::uint32_t>(std::llround(seconds * 1000.0)));
  sb->resume_clock();
  check(L, ctx, "move", status);
  return 0;
}

int l_stop(lua_State* L) {
  SkillContext* ctx = SkillContext::from(L);
  require_permission(L, ctx, "motion", "stop");
  need(L, ctx, ctx->api->stop != nullptr, "stop");
  check(L, ctx, "stop", ctx->api->stop(ctx->host));
  return 0;
}

int l_tilt_head(lua_State* L) {
  SkillContext* ctx = SkillContext::from(L);
  const lua_Integer degrees = luaL_checkinteger(L, 1);
  luaL_argcheck(L, degrees >= -30 && degrees <= 30, 1, "degrees must be -30..30");
  require_permission(L, ctx, "motion", "tilt_head");
  need(L, ctx, ctx->api->tilt_head != nullptr, "tilt_head");
  check(L, ctx, "tilt_head", ctx->api->tilt_head(ctx->host, static_cast<std::int32_t>(degrees)));
  return 0;
}

// --- going places (Robot API 1.2) ----------------------------------------------------------

// True when the host's table reaches `member` (an older host's table ends before it).
#define MARVIN_HAS_API(ctx, member)                                                  \
  ((ctx)->api->struct_size >= offsetof(marvin_robot_api, member) + sizeof(void*) && \
   (ctx)->api->member != nullptr)

// marvin.go_to(place): true once there; false and the reason when the place is unknown or
// the robot gave up ("the kitchen door is blocked"). "stop" ends the request, as move does.
int l_go_to(lua_State* L) {
  SkillContext* ctx = SkillContext::from(L);
  const char* place = luaL_checkstring(L, 1);
  require_permission(L, ctx, "motion", "go_to");
  need(L, ctx, MARVIN_HAS_API(ctx, go_to), "go_to");
  Sandbox* sb = ctx->sandbox.get();
  sb->pause_clock();  // the body's time is not the script's
  const marvin_status status = ctx->api->go_to(ctx->host, place);
  sb->resume_clock();
  if (status == MARVIN_ERR_NOT_FOUND || status == MARVIN_ERR_UNAVAILABLE) {
    lua_pushboolean(L, 0);
    lua_pushstring(L, ctx->api->last_error(ctx->host));
    return 2;
  }
  check(L, ctx, "go_to", status);
  lua_pushboolean(L, 1);
  return 1;
}

// Runs protected (lua_pcall): calls on_event (index 1) with the event table; its result.
int call_guide_event(lua_State* L) {
  SkillContext* ctx = SkillContext::from(L);
  push_json(L, ctx->guide_event);
  lua_call(L, 1, 1);
  return 1;
}

// guide_to's on_event: `user` is the skill's lua_State, on_event at stack index 3. Nothing
// here may raise a Lua error (the host's C++ frames are below): the Lua function runs
// under lua_pcall; a Lua error stops the trip and l_guide_to raises it afterwards.
int guide_event_trampoline(void* user, const char* event_json) {
  auto* L = static_cast<lua_State*>(user);
  SkillContext* ctx = SkillContext::from(L);
  try {
    ctx->guide_event = nlohmann::json::parse(event_json);
  } catch (...) {
    return 1;
  }
  if (!lua_checkstack(L, 4)) return 1;
  Sandbox* sb = ctx->sandbox.get();
  sb->resume_clock();  // the script's own time counts again while it runs
  lua_pushcfunction(L, call_guide_event);
  lua_pushvalue(L, 3);
  const int status = lua_pcall(L, 1, 1, 0);
  sb->pause_clock();
  if (status != LUA_OK) {
    try {
      const char* why = lua_tostring(L, -1);
      ctx->message = why ? why : "an error";
    } catch (...) {
    }
    ctx->guide_failed = true;
    lua_pop(L, 1);
    return 1;
  }
  const bool stop = lua_isboolean(L, -1) && !lua_toboolean(L, -1);
  lua_pop(L, 1);
  return stop ? 1 : 0;
}

// ok, why = marvin.guide_to(place [, speed_percent [, on_event]]): go_to for leading a
// person, at speed_percent (10..100; default 50) of the normal speed, calling
// on_event(event) with each thing worth telling on the way (a table: event, distance_m,
// distance_left_m, turn, kind, stopped); on_event returning false stops the trip.
int l_guide_to(lua_State* L) {
  SkillContext* ctx = SkillContext::from(L);
  const char* place = luaL_checkstring(L, 1);
  const lua_Integer speed = luaL_optinteger(L, 2, 50);
  const bool has_event = !lua_isnoneornil(L, 3);
  if (has_event) luaL_checktype(L, 3, LUA_TFUNCTION);
  lua_settop(L, 3);
  if (speed < 10 || speed > 100) {
    return luaL_error(L, "marvin.guide_to: speed_percent must be 10 to 100, got %d",
                      static_cast<int>(speed));
  }
  require_permission(L, ctx, "motion", "guide_to");
  need(L, ctx, MARVIN_HAS_API(ctx, guide_to), "guide_to");
  Sandbox* sb = ctx->sandbox.get();
  ctx->guide_failed = false;
  sb->pause_clock();  // the body's time is not the script's
  const marvin_status status =
      ctx->api->guide_to(ctx->host, place, static_cast<std::uint32_t>(speed),
                         has_event ? guide_event_trampoline : nullptr, L);
  sb->resume_clock();
  if (ctx->guide_failed) return luaL_error(L, "%s", ctx->message.c_str());
  if (status == MARVIN_ERR_NOT_FOUND || status == MARVIN_ERR_UNAVAILABLE) {
    lua_pushboolean(L, 0);
    lua_pushstring(L, ctx->api->last_error(ctx->host));
    return 2;
  }
  check(L, ctx, "guide_to", status);
  lua_pushboolean(L, 1);
  return 1;
}

// marvin.where_am_i(): the room's name, or nil between rooms.
int l_where_am_i(lua_State* L) {
  SkillContext* ctx = SkillContext::from(L);
  require_permission(L, ctx, "sensors", "where_am_i");
  need(L, ctx, MARVIN_HAS_API(ctx, where_am_i), "where_am_i");
  const marvin_status status = ctx->call_text(
      [ctx](marvin_text_out* out) { return ctx->api->where_am_i(ctx->host, out); });
  if (status == MARVIN_ERR_NOT_FOUND) {
    lua_pushnil(L);
    return 1;
  }
  check(L, ctx, "where_am_i", status);
  lua_pushlstring(L, ctx->text.data(), ctx->text.size());
  return 1;
}

#undef MARVIN_HAS_API

// --- time and log ------------------------------------------------------------------------------

int l_now(lua_State* L) {
  SkillContext* ctx = SkillContext::from(L);
  need(L, ctx, ctx->api->now != nullptr, "now");
  std::int64_t now = 0;
  check(L, ctx, "now", ctx->api->now(ctx->host, &now));
  lua_pushinteger(L, now / 1000);
  return 1;
}

int l_log(lua_State* L) {
  SkillContext* ctx = SkillContext::from(L);
  static const char* const levels[] = {"debug", "info", "warning", "error", nullptr};
  const int level = luaL_checkoption(L, 2, "info", levels);
  std::size_t len = 0;
  const char* text = luaL_tolstring(L, 1, &len);
  ctx->sandbox->emit(static_cast<LogLevel>(level), std::string_view(text, len));
  return 0;
}

// --- schedules ----------------------------------------------------------------------------------

int l_schedule_add(lua_State* L) {
  SkillContext* ctx = SkillContext::from(L);
  require_permission(L, ctx, "schedule", "schedule.add");
  need(L, ctx, ctx->api->schedule_add != nullptr, "schedule.add");
  table_to_json_text(L, ctx, 1, "schedule.add");
  try {
    ctx->message = ctx->text;
  } catch (...) {
  }
  const marvin_status status = ctx->call_text([ctx](marvin_text_out* out) {
    return ctx->api->schedule_add(ctx->host, ctx->message.c_str(), out);
  });
  check(L, ctx, "schedule.add", status);
  push_json_text(L, ctx, "schedule.add");
  return 1;
}

int l_schedule_list(lua_State* L) {
  SkillContext* ctx = SkillContext::from(L);
  require_permission(L, ctx, "schedule", "schedule.list");
  need(L, ctx, ctx->api->schedule_list != nullptr && ctx->api->now != nullptr, "schedule.list");
  std::int64_t now = 0;
  check(L, ctx, "schedule.list", ctx->api->now(ctx->host, &now));
  const lua_Integer from = luaL_optinteger(L, 1, now / 1000);
  const lua_Integer to = luaL_optinteger(L, 2, from + kDefaultListDays * 24 * 3600);
  const marvin_status status = ctx->call_text([ctx, from, to](marvin_text_out* out) {
    return ctx->api->schedule_list(ctx->host, from * 1000, to * 1000, out);
  });
  check(L, ctx, "schedule.list", status);
  push_json_text(L, ctx, "schedule.list");
  return 1;
}

int l_schedule_remove(lua_State* L) {
  SkillContext* ctx = SkillContext::from(L);
  const lua_Integer id = luaL_checkinteger(L, 1);
  require_permission(L, ctx, "schedule", "schedule.remove");
  need(L, ctx, ctx->api->schedule_remove != nullptr, "schedule.remove");
  const marvin_status status = ctx->api->schedule_remove(ctx->host, id);
  if (status == MARVIN_ERR_NOT_FOUND) {
    lua_pushboolean(L, 0);
    return 1;
  }
  check(L, ctx, "schedule.remove", status);
  lua_pushboolean(L, 1);
  return 1;
}

// --- contacts ---------------------------------------------------------------------------------------

int l_contacts_find(lua_State* L) {
  SkillContext* ctx = SkillContext::from(L);
  const char* name = luaL_checkstring(L, 1);
  require_permission(L, ctx, "contacts", "contacts.find");
  need(L, ctx, ctx->api->contacts_find != nullptr, "contacts.find");
  const marvin_status status = ctx->call_text([ctx, name](marvin_text_out* out) {
    return ctx->api->contacts_find(ctx->host, name, out);
  });
  check(L, ctx, "contacts.find", status);
  push_json_text(L, ctx, "contacts.find");
  return 1;
}

int l_contacts_add(lua_State* L) {
  SkillContext* ctx = SkillContext::from(L);
  require_permission(L, ctx, "contacts", "contacts.add");
  need(L, ctx, ctx->api->contacts_add != nullptr, "contacts.add");
  table_to_json_text(L, ctx, 1, "contacts.add");
  try {
    ctx->message = ctx->text;
  } catch (...) {
  }
  const marvin_status status = ctx->call_text([ctx](marvin_text_out* out) {
    return ctx->api->contacts_add(ctx->host, ctx->message.c_str(), out);
  });
  check(L, ctx, "contacts.add", status);
  push_json_text(L, ctx, "contacts.add");
  return 1;
}

int l_people(lua_State* L) {
  SkillContext* ctx = SkillContext::from(L);
  require_permission(L, ctx, "contacts", "contacts.people");
  need(L, ctx, ctx->api->people_list != nullptr, "contacts.people");
  const marvin_status status = ctx->call_text(
      [ctx](marvin_text_out* out) { return ctx->api->people_list(ctx->host, out); });
  check(L, ctx, "contacts.people", status);
  push_json_text(L, ctx, "contacts.people");
  return 1;
}

// --- smart home (Robot API 1.2) ---------------------------------------------------------------------

int l_home_devices(lua_State* L) {
  SkillContext* ctx = SkillContext::from(L);
  require_permission(L, ctx, "smarthome", "home.devices");
  need(L, ctx, ctx->api->smarthome_devices != nullptr, "home.devices");
  const marvin_status status = ctx->call_text(
      [ctx](marvin_text_out* out) { return ctx->api->smarthome_devices(ctx->host, out); });
  check(L, ctx, "home.devices", status);
  push_json_text(L, ctx, "home.devices");
  return 1;
}

// home.set(device, "on" | "off" | {on=, brightness=}) -> true once the device reported it,
// or false and the reason when it could not be done (no broker, no answer, offline).
int l_home_set(lua_State* L) {
  SkillContext* ctx = SkillContext::from(L);
  const char* device = luaL_checkstring(L, 1);
  require_permission(L, ctx, "smarthome", "home.set");
  need(L, ctx, ctx->api->smarthome_set != nullptr, "home.set");
  std::string state;
  if (lua_type(L, 2) == LUA_TSTRING) {
    state = lua_tostring(L, 2);
  } else {
    table_to_json_text(L, ctx, 2, "home.set");
    state = ctx->text;
  }
  const marvin_status status = ctx->api->smarthome_set(ctx->host, device, state.c_str());
  if (status == MARVIN_ERR_UNAVAILABLE) {
    lua_pushboolean(L, 0);
    lua_pushstring(L, ctx->api->last_error(ctx->host));
    return 2;
  }
  check(L, ctx, "home.set", status);
  lua_pushboolean(L, 1);
  return 1;
}

// --- phone calls (Robot API 1.3) -----------------------------------------------------------------

// Pushes true, or false and the reason for the statuses a skill is expected to handle
// (`soft`); raises a Lua error for the others.
int push_done(lua_State* L, SkillContext* ctx, const char* what, marvin_status status,
              std::initializer_list<marvin_status> soft) {
  for (marvin_status s : soft) {
    if (status == s) {
      lua_pushboolean(L, 0);
      lua_pushstring(L, ctx->api->last_error(ctx->host));
      return 2;
    }
  }
  check(L, ctx, what, status);
  lua_pushboolean(L, 1);
  return 1;
}

int l_phone_resolve(lua_State* L) {
  SkillContext* ctx = SkillContext::from(L);
  const char* who = luaL_checkstring(L, 1);
  require_permission(L, ctx, "phone", "phone.resolve");
  need(L, ctx, ctx->api->phone_resolve != nullptr, "phone.resolve");
  const marvin_status status = ctx->call_text(
      [ctx, who](marvin_text_out* out) { return ctx->api->phone_resolve(ctx->host, who, out); });
  check(L, ctx, "phone.resolve", status);
  push_json_text(L, ctx, "phone.resolve");
  return 1;
}

// phone.dial(number [, name]) -> true once dialling started, or false and why.
int l_phone_dial(lua_State* L) {
  SkillContext* ctx = SkillContext::from(L);
  const char* number = luaL_checkstring(L, 1);
  const char* name = luaL_optstring(L, 2, "");
  require_permission(L, ctx, "phone", "phone.dial");
  need(L, ctx, ctx->api->phone_dial != nullptr, "phone.dial");
  return push_done(L, ctx, "phone.dial", ctx->api->phone_dial(ctx->host, number, name),
                   {MARVIN_ERR_UNAVAILABLE, MARVIN_ERR_INVALID});
}

int l_phone_hang_up(lua_State* L) {
  SkillContext* ctx = SkillContext::from(L);
  require_permission(L, ctx, "phone", "phone.hang_up");
  need(L, ctx, ctx->api->phone_hang_up != nullptr, "phone.hang_up");
  return push_done(L, ctx, "phone.hang_up", ctx->api->phone_hang_up(ctx->host),
                   {MARVIN_ERR_NOT_FOUND});
}

int l_phone_answer(lua_State* L) {
  SkillContext* ctx = SkillContext::from(L);
  require_permission(L, ctx, "phone", "phone.answer");
  need(L, ctx, ctx->api->phone_answer != nullptr, "phone.answer");
  return push_done(L, ctx, "phone.answer", ctx->api->phone_answer(ctx->host),
                   {MARVIN_ERR_NOT_FOUND});
}

int l_phone_decline(lua_State* L) {
  SkillContext* ctx = SkillContext::from(L);
  require_permission(L, ctx, "phone", "phone.decline");
  need(L, ctx, ctx->api->phone_decline != nullptr, "phone.decline");
  return push_done(L, ctx, "phone.decline", ctx->api->phone_decline(ctx->host),
                   {MARVIN_ERR_NOT_FOUND});
}

int l_phone_state(lua_State* L) {
  SkillContext* ctx = SkillContext::from(L);
  require_permission(L, ctx, "phone", "phone.state");
  need(L, ctx, ctx->api->phone_state != nullptr, "phone.state");
  const marvin_status status = ctx->call_text(
      [ctx](marvin_text_out* out) { return ctx->api->phone_state(ctx->host, out); });
  check(L, ctx, "phone.state", status);
  push_json_text(L, ctx, "phone.state");
  return 1;
}

// phone.wait_event(timeout_ms) -> the event as a table, or nil when nothing happened.
int l_phone_wait_event(lua_State* L) {
  SkillContext* ctx = SkillContext::from(L);
  const lua_Integer ms = luaL_checkinteger(L, 1);
  luaL_argcheck(L, ms >= 0 && ms <= 600000, 1, "milliseconds from 0 to 600000");
  require_permission(L, ctx, "phone", "phone.wait_event");
  need(L, ctx, ctx->api->phone_wait_event != nullptr, "phone.wait_event");
  const auto timeout = static_cast<uint32_t>(ms);
  const marvin_status status = ctx->call_text([ctx, timeout](marvin_text_out* out) {
    return ctx->api->phone_wait_event(ctx->host, timeout, out);
  });
  if (status == MARVIN_ERR_NOT_FOUND) {
    lua_pushnil(L);
    return 1;
  }
  check(L, ctx, "phone.wait_event", status);
  push_json_text(L, ctx, "phone.wait_event");
  return 1;
}

int l_phone_call_for_help(lua_State* L) {
  SkillContext* ctx = SkillContext::from(L);
  require_permission(L, ctx, "phone", "phone.call_for_help");
  need(L, ctx, ctx->api->phone_call_for_help != nullptr, "phone.call_for_help");
  return push_done(L, ctx, "phone.call_for_help", ctx->api->phone_call_for_help(ctx->host),
                   {MARVIN_ERR_NOT_FOUND, MARVIN_ERR_UNAVAILABLE});
}

// --- storage ------------------------------------------------------------------------------------------

int l_storage_get(lua_State* L) {
  SkillContext* ctx = SkillContext::from(L);
  const char* key = luaL_checkstring(L, 1);
  require_permission(L, ctx, "storage", "storage.get");
  need(L, ctx, ctx->api->storage_get != nullptr, "storage.get");
  const marvin_status status = ctx->call_text([ctx, key](marvin_text_out* out) {
    return ctx->api->storage_get(ctx->host, key, out);
  });
  if (status == MARVIN_ERR_NOT_FOUND) {
    lua_pushnil(L);
    return 1;
  }
  check(L, ctx, "storage.get", status);
  lua_pushlstring(L, ctx->text.data(), ctx->text.size());
  return 1;
}

int l_storage_remove(lua_State* L) {
  SkillContext* ctx = SkillContext::from(L);
  const char* key = luaL_checkstring(L, 1);
  require_permission(L, ctx, "storage", "storage.remove");
  need(L, ctx, ctx->api->storage_remove != nullptr, "storage.remove");
  const marvin_status status = ctx->api->storage_remove(ctx->host, key);
  if (status != MARVIN_ERR_NOT_FOUND) check(L, ctx, "storage.remove", status);
  return 0;
}

int l_storage_set(lua_State* L) {
  SkillContext* ctx = SkillContext::from(L);
  const char* key = luaL_checkstring(L, 1);
  if (lua_isnoneornil(L, 2)) return l_storage_remove(L);
  const int type = lua_type(L, 2);
  luaL_argexpected(L, type == LUA_TSTRING || type == LUA_TNUMBER || type == LUA_TBOOLEAN, 2,
                   "string, number, boolean or nil");
  std::size_t len = 0;
  const char* value = luaL_tolstring(L, 2, &len);
  require_permission(L, ctx, "storage", "storage.set");
  need(L, ctx, ctx->api->storage_set != nullptr, "storage.set");
  check(L, ctx, "storage.set", ctx->api->storage_set(ctx->host, key, value, len));
  return 0;
}

// --- vision (Robot API 1.2) ------------------------------------------------------------------------

// A 1.2 slot exists in the host's table (an older host's table ends before it).
#define MARVIN_HAS_SLOT(ctx, member)                                                 \
  ((ctx)->api->struct_size >= offsetof(marvin_robot_api, member) + sizeof(void*) && \
   (ctx)->api->member != nullptr)

int l_vision_look(lua_State* L) {
  SkillContext* ctx = SkillContext::from(L);
  require_permission(L, ctx, "camera", "vision.look");
  need(L, ctx, MARVIN_HAS_SLOT(ctx, vision_look), "vision.look");
  const marvin_status status = ctx->call_text(
      [ctx](marvin_text_out* out) { return ctx->api->vision_look(ctx->host, out); });
  check(L, ctx, "vision.look", status);
  push_json_text(L, ctx, "vision.look");
  return 1;
}

int l_vision_photo(lua_State* L) {
  SkillContext* ctx = SkillContext::from(L);
  require_permission(L, ctx, "camera", "vision.photo");
  need(L, ctx, MARVIN_HAS_SLOT(ctx, vision_capture_photo), "vision.photo");
  const marvin_status status = ctx->call_text(
      [ctx](marvin_text_out* out) { return ctx->api->vision_capture_photo(ctx->host, out); });
  check(L, ctx, "vision.photo", status);
  lua_pushlstring(L, ctx->text.data(), ctx->text.size());
  return 1;
}

int l_vision_enroll(lua_State* L) {
  SkillContext* ctx = SkillContext::from(L);
  const char* name = luaL_checkstring(L, 1);
  const lua_Integer frames = luaL_optinteger(L, 2, 5);
  luaL_argcheck(L, frames >= 1 && frames <= 20, 2, "frames must be 1..20");
  require_permission(L, ctx, "faces", "vision.enroll");
  need(L, ctx, MARVIN_HAS_SLOT(ctx, vision_enroll_face), "vision.enroll");
  const marvin_status status = ctx->call_text([ctx, name, frames](marvin_text_out* out) {
    return ctx->api->vision_enroll_face(ctx->host, name, static_cast<uint32_t>(frames), out);
  });
  check(L, ctx, "vision.enroll", status);
  push_json_text(L, ctx, "vision.enroll");
  return 1;
}

int l_vision_forget(lua_State* L) {
  SkillContext* ctx = SkillContext::from(L);
  const char* name = luaL_checkstring(L, 1);
  require_permission(L, ctx, "faces", "vision.forget");
  need(L, ctx, MARVIN_HAS_SLOT(ctx, vision_forget_face), "vision.forget");
  const marvin_status status = ctx->api->vision_forget_face(ctx->host, name);
  if (status == MARVIN_ERR_NOT_FOUND) {
    lua_pushboolean(L, 0);
    return 1;
  }
  check(L, ctx, "vision.forget", status);
  lua_pushboolean(L, 1);
  return 1;
}

int l_vision_teach(lua_State* L) {
  SkillContext* ctx = SkillContext::from(L);
  const char* name = luaL_checkstring(L, 1);
  require_permission(L, ctx, "camera", "vision.teach");
  need(L, ctx, MARVIN_HAS_SLOT(ctx, vision_teach_object), "vision.teach");
  check(L, ctx, "vision.teach", ctx->api->vision_teach_object(ctx->host, name));
  return 0;
}

int l_vision_find(lua_State* L) {
  SkillContext* ctx = SkillContext::from(L);
  const char* name = luaL_checkstring(L, 1);
  require_permission(L, ctx, "camera", "vision.find");
  need(L, ctx, ctx->api->vision_find_object != nullptr, "vision.find");
  const marvin_status status = ctx->call_text([ctx, name](marvin_text_out* out) {
    return ctx->api->vision_find_object(ctx->host, name, out);
  });
  if (status == MARVIN_ERR_NOT_FOUND) {
    lua_pushnil(L);
    return 1;
  }
  check(L, ctx, "vision.find", status);
  push_json_text(L, ctx, "vision.find");
  return 1;
}

// --- finding and guarding (Robot API 1.3) ------------------------------------------------------

// marvin.finding.look_around([stops]): turns a full circle looking; {stops, seen = {...}}.
int l_look_around(lua_State* L) {
  SkillContext* ctx = SkillContext::from(L);
  const auto stops = static_cast<std::uint32_t>(luaL_optinteger(L, 1, 0));
  require_permission(L, ctx, "camera", "finding.look_around");
  require_permission(L, ctx, "motion", "finding.look_around");
  need(L, ctx, MARVIN_HAS_SLOT(ctx, look_around), "finding.look_around");
  Sandbox* sb = ctx->sandbox.get();
  sb->pause_clock();  // the body's time is not the script's
  const marvin_status status = ctx->call_text(
      [ctx, stops](marvin_text_out* out) { return ctx->api->look_around(ctx->host, stops, out); });
  sb->resume_clock();
  check(L, ctx, "finding.look_around", status);
  push_json_text(L, ctx, "finding.look_around");
  return 1;
}

// marvin.finding.sightings([what [, since_ms]]): where things were seen, newest first.
int l_sightings(lua_State* L) {
  SkillContext* ctx = SkillContext::from(L);
  const char* what = luaL_optstring(L, 1, "");
  const auto since = static_cast<std::int64_t>(luaL_optinteger(L, 2, 0));
  require_permission(L, ctx, "camera", "finding.sightings");
  need(L, ctx, MARVIN_HAS_SLOT(ctx, sightings_find), "finding.sightings");
  const marvin_status status = ctx->call_text([ctx, what, since](marvin_text_out* out) {
    return ctx->api->sightings_find(ctx->host, what, since, out);
  });
  check(L, ctx, "finding.sightings", status);
  push_json_text(L, ctx, "finding.sightings");
  return 1;
}

// marvin.finding.rooms(): the rooms in the order a search visits them.
int l_rooms_to_search(lua_State* L) {
  SkillContext* ctx = SkillContext::from(L);
  require_permission(L, ctx, "sensors", "finding.rooms");
  need(L, ctx, MARVIN_HAS_SLOT(ctx, rooms_to_search), "finding.rooms");
  const marvin_status status = ctx->call_text(
      [ctx](marvin_text_out* out) { return ctx->api->rooms_to_search(ctx->host, out); });
  check(L, ctx, "finding.rooms", status);
  push_json_text(L, ctx, "finding.rooms");
  return 1;
}

// marvin.finding.guard(mode): 1 on, 0 off (false and the reason unless a known face is in
// view), -1 report; the state table {on, since_unix_ms, alerts, by}.
int l_guard(lua_State* L) {
  SkillContext* ctx = SkillContext::from(L);
  const auto mode = static_cast<std::int32_t>(luaL_checkinteger(L, 1));
  require_permission(L, ctx, "camera", "finding.guard");
  need(L, ctx, MARVIN_HAS_SLOT(ctx, guard), "finding.guard");
  const marvin_status status = ctx->call_text(
      [ctx, mode](marvin_text_out* out) { return ctx->api->guard(ctx->host, mode, out); });
  if (status == MARVIN_ERR_PERMISSION && mode == 0) {
    lua_pushboolean(L, 0);
    lua_pushstring(L, ctx->api->last_error(ctx->host));
    return 2;
  }
  check(L, ctx, "finding.guard", status);
  push_json_text(L, ctx, "finding.guard");
  return 1;
}

// marvin.finding.events([kind [, since_ms]]): the owner's event log, newest first.
int l_events(lua_State* L) {
  SkillContext* ctx = SkillContext::from(L);
  const char* kind = luaL_optstring(L, 1, "");
  const auto since = static_cast<std::int64_t>(luaL_optinteger(L, 2, 0));
  require_permission(L, ctx, "events", "finding.events");
  need(L, ctx, MARVIN_HAS_SLOT(ctx, events_list), "finding.events");
  const marvin_status status = ctx->call_text([ctx, kind, since](marvin_text_out* out) {
    return ctx->api->events_list(ctx->host, kind, since, out);
  });
  check(L, ctx, "finding.events", status);
  push_json_text(L, ctx, "finding.events");
  return 1;
}

void set_functions(lua_State* L, const luaL_Reg* functions) { luaL_setfuncs(L, functions, 0); }

}  // namespace

void install_marvin_api(lua_State* L, SkillContext* ctx) {
  (void)ctx;
  lua_createtable(L, 0, 0);
  lua_rawsetp(L, LUA_REGISTRYINDEX, &kHandlersKey);
  lua_createtable(L, 0, 0);
  lua_rawsetp(L, LUA_REGISTRYINDEX, &kTimersKey);

  lua_createtable(L, 0, 16);
  static const luaL_Reg top[] = {
      {"on", l_on},       {"say", l_say},     {"ask", l_ask},   {"light", l_light},
      {"move", l_move},   {"stop", l_stop},   {"tilt_head", l_tilt_head},
      {"go_to", l_go_to}, {"guide_to", l_guide_to}, {"where_am_i", l_where_am_i},
      {"now", l_now},     {"after", l_after}, {"log", l_log},   {nullptr, nullptr}};
  set_functions(L, top);

  lua_createtable(L, 0, 3);
  static const luaL_Reg schedule[] = {{"add", l_schedule_add},
                                      {"list", l_schedule_list},
                                      {"remove", l_schedule_remove},
                                      {nullptr, nullptr}};
  set_functions(L, schedule);
  Sandbox::make_read_only(L, "marvin.schedule");
  lua_setfield(L, -2, "schedule");

  lua_createtable(L, 0, 3);
  static const luaL_Reg contacts[] = {{"find", l_contacts_find},
                                      {"add", l_contacts_add},
                                      {"people", l_people},
                                      {nullptr, nullptr}};
  set_functions(L, contacts);
  Sandbox::make_read_only(L, "marvin.contacts");
  lua_setfield(L, -2, "contacts");

  lua_createtable(L, 0, 2);
  static const luaL_Reg home[] = {{"devices", l_home_devices}, {"set", l_home_set}, {nullptr, nullptr}};
  set_functions(L, home);
  Sandbox::make_read_only(L, "marvin.home");
  lua_setfield(L, -2, "home");

  lua_createtable(L, 0, 8);
  static const luaL_Reg phone[] = {{"resolve", l_phone_resolve},
                                   {"dial", l_phone_dial},
                                   {"hang_up", l_phone_hang_up},
                                   {"answer", l_phone_answer},
                                   {"decline", l_phone_decline},
                                   {"state", l_phone_state},
                                   {"wait_event", l_phone_wait_event},
                                   {"call_for_help", l_phone_call_for_help},
                                   {nullptr, nullptr}};
  set_functions(L, phone);
  Sandbox::make_read_only(L, "marvin.phone");
  lua_setfield(L, -2, "phone");

  lua_createtable(L, 0, 3);
  static const luaL_Reg storage[] = {{"get", l_storage_get},
                                     {"set", l_storage_set},
                                     {"remove", l_storage_remove},
                                     {nullptr, nullptr}};
  set_functions(L, storage);
  Sandbox::make_read_only(L, "marvin.storage");
  lua_setfield(L, -2, "storage");

  lua_createtable(L, 0, 4);
  static const luaL_Reg vision[] = {{"look", l_vision_look},
                                    {"photo", l_vision_photo},
                                    {"enroll", l_vision_enroll},
                                    {"forget", l_vision_forget},
                                    {"teach", l_vision_teach},
                                    {"find", l_vision_find},
                                    {nullptr, nullptr}};
  set_functions(L, vision);
  Sandbox::make_read_only(L, "marvin.vision");
  lua_setfield(L, -2, "vision");

  lua_createtable(L, 0, 5);
  static const luaL_Reg finding[] = {{"look_around", l_look_around},
                                     {"sightings", l_sightings},
                                     {"rooms", l_rooms_to_search},
                                     {"guard", l_guard},
                                     {"events", l_events},
                                     {nullptr, nullptr}};
  set_functions(L, finding);
  Sandbox::make_read_only(L, "marvin.finding");
  lua_setfield(L, -2, "finding");

  Sandbox::make_read_only(L, "marvin");
  Sandbox::from(L)->set_protected_global(L, "marvin");
}

}  // namespace marvin::scripting
