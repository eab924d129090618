// The sandbox: allocator, hooks, the allowlisted environment and the wrappers that keep a
// tripped budget tripped.
//
// A word on errors: Lua reports errors with longjmp. Every lua_CFunction below therefore
// keeps no C++ object with a destructor alive across a call that may raise; text the host
// computes lives in members (scratch_) or in Lua values. Host-side work on the state runs
// inside protect() so a memory error never reaches Lua's panic handler.
#include "scripting/sandbox.h"

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <system_error>

#include <lua.hpp>

#include "scripting/safe_string.h"

namespace marvin::scripting {
namespace {

// Registry keys (addresses are unique).
char kGlobalsKey;   // the skill's global table
char kBaseKey;      // what the sandbox provides (read through the globals' __index)
char kReadOnlyKey;  // set of read-only proxies (weak keys)
char kModulesKey;   // require() cache
char kLoadingKey;   // marks a module being loaded (require loops)

// Host code may use this much beyond the cap (outside script code), so it can still
// describe the error of a skill that exhausted its memory.
constexpr std::size_t kHostReserve = 256u << 10;

void count_hook(lua_State* L, lua_Debug*) {
  Sandbox::from(L)->check_budget(L, static_cast<std::uint64_t>(lua_gethookcount(L)));
}

bool is_read_only(lua_State* L, int index) {
  index = lua_absindex(L, index);
  lua_rawgetp(L, LUA_REGISTRYINDEX, &kReadOnlyKey);
  lua_pushvalue(L, index);
  const bool result = lua_rawget(L, -2) != LUA_TNIL;
  lua_pop(L, 2);
  return result;
}

// True when `key` (at index) names something the sandbox provides as a global.
bool is_sandbox_global(lua_State* L, int key) {
  key = lua_absindex(L, key);
  lua_rawgetp(L, LUA_REGISTRYINDEX, &kBaseKey);
  lua_pushvalue(L, key);
  const bool result = lua_rawget(L, -2) != LUA_TNIL;
  lua_pop(L, 2);
  return result;
}

int refuse_global(lua_State* L, int key) {
  return luaL_error(L, "cannot replace '%s': it is part of the sandbox (use a local variable "
                    "or another name)", luaL_tolstring(L, key, nullptr));
}

// __newindex of read-only proxies. Upvalue 1: the table's name.
int read_only_newindex(lua_State* L) {
  return luaL_error(L, "attempt to modify read-only table '%s'",
                    lua_tostring(L, lua_upvalueindex(1)));
}

// Iterator of pairs() over a proxy: upvalue 1 is the real table, never handed out.
int read_only_next(lua_State* L) {
  lua_settop(L, 2);
  if (lua_next(L, lua_upvalueindex(1)) != 0) return 2;
  lua_pushnil(L);
  return 1;
}

int read_only_pairs(lua_State* L) {
  lua_pushvalue(L, lua_upvalueindex(1));
  lua_pushcclosure(L, read_only_next, 1);
  lua_pushvalue(L, 1);
  lua_pushnil(L);
  return 3;
}

int read_only_len(lua_State* L) {
  lua_pushinteger(L, static_cast<lua_Integer>(lua_rawlen(L, lua_upvalueindex(1))));
  return 1;
}

// __newindex of the globals table: sandbox names cannot be shadowed.
int globals_newindex(lua_State* L) {
  if (is_sandbox_global(L, 2)) return refuse_global(L, 2);
  lua_settop(L, 3);
  lua_rawset(L, 1);
  return 0;
}

// --- wrappers of base functions ---------------------------------------------------------

int finish_pcall(lua_State* L, int status, lua_KContext extra) {
  Sandbox* sb = Sandbox::from(L);
  if (status == LUA_ERRMEM && sb->script_running()) sb->trip(std::string());
  if (sb->tripped()) sb->raise_tripped(L);
  if (status != LUA_OK && status != LUA_YIELD) {
    lua_pushboolean(L, 0);
    lua_pushvalue(L, -2);
    return 2;
  }
  return lua_gettop(L) - static_cast<int>(extra);
}

int sb_pcall(lua_State* L) {
  luaL_checkany(L, 1);
  lua_pushboolean(L, 1);
  lua_insert(L, 1);
  const int status = lua_pcallk(L, lua_gettop(L) - 2, LUA_MULTRET, 0, 0, finish_pcall);
  return finish_pcall(L, status, 0);
}

// The message handler of xpcall, guarded: a budget error is raised from inside the count
// hook, where Lua runs message handlers with hooks off, so once tripped the script's
// handler is skipped (it could loop forever unseen). Upvalue 1: the script's handler.
int guarded_handler(lua_State* L) {
  if (Sandbox::from(L)->tripped()) return 1;
  lua_pushvalue(L, lua_upvalueindex(1));
  lua_insert(L, 1);
  lua_call(L, lua_gettop(L) - 1, 1);
  return 1;
}

int sb_xpcall(lua_State* L) {
  const int n = lua_gettop(L);
  luaL_checktype(L, 2, LUA_TFUNCTION);
  lua_pushvalue(L, 2);
  lua_pushcclosure(L, guarded_handler, 1);
  lua_replace(L, 2);
  lua_pushboolean(L, 1);
  lua_pushvalue(L, 1);
  lua_rotate(L, 3, 2);
  const int status = lua_pcallk(L, n - 2, LUA_MULTRET, 2, 2, finish_pcall);
  return finish_pcall(L, status, 2);
}

// Calls the original C function in upvalue 1 with every argument, then re-raises a trip.
int call_then_check(lua_State* L) {
  const int n = lua_gettop(L);
  lua_pushvalue(L, lua_upvalueindex(1));
  lua_insert(L, 1);
  lua_call(L, n, LUA_MULTRET);
  Sandbox* sb = Sandbox::from(L);
  if (sb->tripped()) sb->raise_tripped(L);
  return lua_gettop(L);
}

// coroutine.wrap: wraps the original's closure so a trip inside it is re-raised.
int sb_wrap(lua_State* L) {
  lua_pushvalue(L, lua_upvalueindex(1));
  lua_insert(L, 1);
  lua_call(L, lua_gettop(L) - 1, 1);
  lua_pushcclosure(L, call_then_check, 1);
  return 1;
}

int sb_setmetatable(lua_State* L) {
  luaL_checktype(L, 1, LUA_TTABLE);
  const int t = lua_type(L, 2);
  luaL_argexpected(L, t == LUA_TNIL || t == LUA_TTABLE, 2, "nil or table");
  if (is_read_only(L, 1)) return luaL_error(L, "attempt to modify read-only table");
  if (t == LUA_TTABLE) {
    lua_pushliteral(L, "__gc");
    if (lua_rawget(L, 2) != LUA_TNIL) {
      return luaL_error(L, "__gc metamethods are not allowed in skills (Lua runs them outside "
                        "the skill's time and instruction budget)");
    }
    lua_pop(L, 1);
  }
  if (luaL_getmetafield(L, 1, "__metatable") != LUA_TNIL) {
    return luaL_error(L, "cannot change a protected metatable");
  }
  lua_settop(L, 2);
  lua_setmetatable(L, 1);
  return 1;
}

int sb_rawset(lua_State* L) {
  luaL_checktype(L, 1, LUA_TTABLE);
  luaL_checkany(L, 2);
  luaL_checkany(L, 3);
  if (is_read_only(L, 1)) return luaL_error(L, "attempt to modify read-only table");
  lua_rawgetp(L, LUA_REGISTRYINDEX, &kGlobalsKey);
  const bool globals = lua_rawequal(L, 1, -1) != 0;
  lua_pop(L, 1);
  if (globals && is_sandbox_global(L, 2)) return refuse_global(L, 2);
  lua_settop(L, 3);
  lua_rawset(L, 1);
  return 1;
}

int sb_collectgarbage(lua_State* L) {
  const char* option = luaL_optstring(L, 1, "collect");
  if (std::strcmp(option, "collect") == 0) {
    lua_gc(L, LUA_GCCOLLECT);
    lua_pushinteger(L, 0);
    return 1;
  }
  if (std::strcmp(option, "count") == 0) {
    const int kb = lua_gc(L, LUA_GCCOUNT);
    const int bytes = lua_gc(L, LUA_GCCOUNTB);
    lua_pushnumber(L, static_cast<lua_Number>(kb) + static_cast<lua_Number>(bytes) / 1024.0);
    return 1;
  }
  if (std::strcmp(option, "step") == 0) {
    const auto kb = static_cast<int>(luaL_optinteger(L, 2, 0));
    lua_pushboolean(L, lua_gc(L, LUA_GCSTEP, kb));
    return 1;
  }
  if (std::strcmp(option, "isrunning") == 0) {
    lua_pushboolean(L, lua_gc(L, LUA_GCISRUNNING));
    return 1;
  }
  return luaL_error(L, "collectgarbage(\"%s\") is not allowed in skills (allowed: \"collect\", "
                    "\"count\", \"step\", \"isrunning\")", option);
}

int sb_print(lua_State* L) {
  const int n = lua_gettop(L);
  luaL_Buffer b;
  luaL_buffinit(L, &b);
  for (int i = 1; i <= n; ++i) {
    if (i > 1) luaL_addchar(&b, '\t');
    luaL_tolstring(L, i, nullptr);
    luaL_addvalue(&b);
  }
  luaL_pushresult(&b);
  std::size_t len = 0;
  const char* text = lua_tolstring(L, -1, &len);
  Sandbox::from(L)->emit(LogLevel::kInfo, std::string_view(text, len));
  return 0;
}

// load(chunk [, chunkname [, mode [, env]]]): text chunks given as strings only.
int sb_load(lua_State* L) {
  if (lua_type(L, 1) != LUA_TSTRING) {
    return luaL_error(L, "load: skills may only load text chunks given as strings (got a %s)",
                      luaL_typename(L, 1));
  }
  std::size_t len = 0;
  const char* code = lua_tolstring(L, 1, &len);
  const char* name = luaL_optstring(L, 2, "load");
  const int env = lua_isnone(L, 4) ? 0 : 4;
  if (env != 0) luaL_checktype(L, 4, LUA_TTABLE);
  lua_pushfstring(L, "=%s", name);
  const int status = luaL_loadbufferx(L, code, len, lua_tostring(L, -1), "t");
  if (status != LUA_OK) {
    luaL_pushfail(L);
    lua_insert(L, -2);
    return 2;
  }
  if (env != 0) {
    lua_pushvalue(L, env);
  } else {
    lua_rawgetp(L, LUA_REGISTRYINDEX, &kGlobalsKey);
  }
  lua_setupvalue(L, -2, 1);
  return 1;
}

bool valid_module_name(const char* name, std::size_t len) {
  if (len == 0 || len > 100 || name[0] == '.' || name[len - 1] == '.') return false;
  for (std::size_t i = 0; i < len; ++i) {
    const char c = name[i];
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                    c == '_' || c == '-' || (c == '.' && name[i + 1] != '.');
    if (!ok) return false;
  }
  return true;
}

// require(name): NAME.lua (dots are folders) inside the skill's folder, loaded as text.
int sb_require(lua_State* L) {
  std::size_t len = 0;
  const char* name = luaL_checklstring(L, 1, &len);
  lua_settop(L, 1);
  lua_rawgetp(L, LUA_REGISTRYINDEX, &kModulesKey);  // 2
  lua_pushvalue(L, 1);
  if (lua_rawget(L, 2) != LUA_TNIL) {
    if (lua_touserdata(L, -1) == &kLoadingKey) {
      return luaL_error(L, "require(\"%s\"): the module requires itself (a loop of requires)",
                        name);
    }
    return 1;
  }
  lua_pop(L, 1);
  if (!valid_module_name(name, len)) {
    return luaL_error(L, "require(\"%s\"): module names are letters, digits, '_', '-' and dots; "
                      "a skill may only require its own .lua files", name);
  }
  char path[128];
  std::size_t n = 0;
  for (; n < len; ++n) path[n] = name[n] == '.' ? '/' : name[n];
  std::memcpy(path + n, ".lua", 5);
  lua_pushstring(L, path);                             // 3: relative path
  Sandbox::from(L)->load_file(L, lua_tostring(L, 3));  // 4: chunk
  lua_pushvalue(L, 1);
  lua_pushlightuserdata(L, &kLoadingKey);
  lua_rawset(L, 2);
  lua_pushvalue(L, 1);
  lua_call(L, 1, 1);
  if (lua_isnil(L, -1)) {
    lua_pop(L, 1);
    lua_pushboolean(L, 1);
  }
  lua_pushvalue(L, 1);
  lua_pushvalue(L, -2);
  lua_rawset(L, 2);
  return 1;
}

void copy_field(lua_State* L, int from, int to, const char* name) {
  lua_getfield(L, from, name);
  lua_setfield(L, to, name);
}

// Opens library `open` and leaves its table on the stack (not as a global).
void open_library(lua_State* L, const char* name, lua_CFunction open) {
  luaL_requiref(L, name, open, 0);
}

}  // namespace

Sandbox::Sandbox(std::string name, std::filesystem::path folder, Limits limits, Clock clock)
    : name_(std::move(name)), folder_(std::move(folder)), limits_(limits), clock_(std::move(clock)) {
  if (!clock_) clock_ = [] { return std::chrono::steady_clock::now(); };
  L_ = lua_newstate(&Sandbox::allocate, this);
  if (L_ == nullptr) throw std::runtime_error("skill '" + name_ + "': cannot create a Lua state");
  std::string error;
  if (protect(&Sandbox::setup, this, &error) != LUA_OK) {
    lua_close(L_);
    throw std::runtime_error("skill '" + name_ + "': cannot build the Lua sandbox: " + error);
  }
}

Sandbox::~Sandbox() {
  if (L_ != nullptr) lua_close(L_);
}

Sandbox* Sandbox::from(lua_State* L) {
  void* ud = nullptr;
  lua_getallocf(L, &ud);
  return static_cast<Sandbox*>(ud);
}

void* Sandbox::allocate(void* ud, void* ptr, std::size_t old_size, std::size_t new_size) {
  auto* sb = static_cast<Sandbox*>(ud);
  const std::size_t old = ptr != nullptr ? old_size : 0;
  if (new_size == 0) {
    std::free(ptr);
    sb->memory_used_ -= old;
    return nullptr;
  }
  if (new_size > old) {
    const std::size_t limit =
        sb->limits_.memory_bytes + (sb->script_depth_ > 0 ? 0 : kHostReserve);
    if (sb->memory_used_ - old + new_size > limit) {
      sb->note_refusal(new_size);
      return nullptr;
    }
  }
  void* block = std::realloc(ptr, new_size);
  if (block == nullptr) return nullptr;
  sb->memory_used_ = sb->memory_used_ - old + new_size;
  if (new_size > old) sb->refused_size_ = 0;
  return block;
}

// Lua retries a refused allocation once after an emergency collection; a second refusal
// of the same size means the script really holds that much.
void Sandbox::note_refusal(std::size_t size) {
  if (refused_size_ == size && script_depth_ > 0) trip(std::string());
  refused_size_ = size;
}

void Sandbox::trip(const std::string& reason) noexcept {
  if (tripped_) return;
  tripped_ = true;
  try {
    if (reason.empty()) {
      trip_reason_ = "memory limit exceeded (the skill may use " +
                     std::to_string(limits_.memory_bytes / 1024) + " KB)";
    } else {
      trip_reason_ = reason;
    }
  } catch (...) {
    trip_reason_.clear();  // keeps its capacity: no allocation
  }
}

// Adds `count` to the instruction budget and checks the deadline; trips when either is
// exhausted. Returns whether the state is tripped.
bool Sandbox::over_budget(std::uint64_t count) noexcept {
  if (tripped_) return true;
  instructions_ += count;
  try {
    if (instructions_ > limits_.instructions) {
      trip("instruction budget exceeded (" + std::to_string(limits_.instructions) +
           " instructions in one request): is there an endless loop?");
    } else if (!paused_ && clock_() > deadline_) {
      trip("time limit exceeded (" + std::to_string(limits_.wall_time.count()) +
           " ms for one request)");
    } else if (cancel_ && cancel_()) {
      cancelled_ = true;
      trip("cancelled (the user said stop)");
    }
  } catch (...) {
    trip("budget exceeded");
  }
  return tripped_;
}

void Sandbox::check_budget(lua_State* L, std::uint64_t count) {
  if (!over_budget(count)) return;
  // Called from the hook: level 0 is the script's function.
  lua_sethook(L, count_hook, LUA_MASKCOUNT, 1);
  luaL_where(L, 0);
  lua_pushstring(L, trip_reason_.c_str());
  lua_concat(L, 2);
  lua_error(L);
}

void Sandbox::charge(lua_State* L, std::uint64_t steps) {
  if (over_budget(steps)) raise_tripped(L);
}

void Sandbox::raise_tripped(lua_State* L) {
  // Called from a C function: level 1 is the script's line that called it.
  lua_sethook(L, count_hook, LUA_MASKCOUNT, 1);
  luaL_where(L, 1);
  lua_pushstring(L, trip_reason_.c_str());
  lua_concat(L, 2);
  lua_error(L);
  std::abort();  // lua_error does not return
}

void Sandbox::begin_invocation() {
  instructions_ = 0;
  tripped_ = false;
  cancelled_ = false;
  trip_reason_.clear();
  refused_size_ = 0;
  output_used_ = 0;
  output_capped_ = false;
  paused_ = false;
  deadline_ = clock_() + limits_.wall_time;
  lua_sethook(L_, count_hook, LUA_MASKCOUNT, kHookInterval);
}

void Sandbox::end_invocation() { paused_ = false; }

void Sandbox::pause_clock() {
  if (paused_) return;
  paused_ = true;
  paused_at_ = clock_();
}

void Sandbox::resume_clock() {
  if (!paused_) return;
  paused_ = false;
  deadline_ += clock_() - paused_at_;
}

bool Sandbox::emit(LogLevel level, std::string_view text) {
  try {
    if (output_capped_) return false;
    if (output_used_ + text.size() > limits_.output_bytes) {
      output_capped_ = true;
      const std::string notice = "output limit reached (" + std::to_string(limits_.output_bytes) +
                                 " bytes per request); further output of this request is dropped";
      if (output_) {
        output_(LogLevel::kWarning, notice);
      } else {
        marvin::log(LogLevel::kWarning, "skill:" + name_, notice);
      }
      return false;
    }
    output_used_ += text.size();
    if (output_) {
      output_(level, text);
    } else {
      marvin::log(level, "skill:" + name_, text);
    }
    return true;
  } catch (...) {
    return false;
  }
}

void Sandbox::push_globals(lua_State* L) const { lua_rawgetp(L, LUA_REGISTRYINDEX, &kGlobalsKey); }

void Sandbox::make_read_only(lua_State* L, const char* name) {
  const int real = lua_gettop(L);
  lua_createtable(L, 0, 0);  // the proxy
  lua_createtable(L, 0, 5);  // its metatable
  lua_pushvalue(L, real);
  lua_setfield(L, -2, "__index");
  lua_pushstring(L, name);
  lua_pushcclosure(L, read_only_newindex, 1);
  lua_setfield(L, -2, "__newindex");
  lua_pushvalue(L, real);
  lua_pushcclosure(L, read_only_pairs, 1);
  lua_setfield(L, -2, "__pairs");
  lua_pushvalue(L, real);
  lua_pushcclosure(L, read_only_len, 1);
  lua_setfield(L, -2, "__len");
  lua_pushliteral(L, "read-only");
  lua_setfield(L, -2, "__metatable");
  lua_setmetatable(L, -2);
  lua_rawgetp(L, LUA_REGISTRYINDEX, &kReadOnlyKey);
  lua_pushvalue(L, -2);
  lua_pushboolean(L, 1);
  lua_rawset(L, -3);
  lua_pop(L, 1);
  lua_remove(L, real);
}

void Sandbox::set_protected_global(lua_State* L, const char* name) {
  lua_rawgetp(L, LUA_REGISTRYINDEX, &kBaseKey);
  lua_insert(L, -2);
  lua_setfield(L, -2, name);
  lua_pop(L, 1);
}

int Sandbox::setup(lua_State* L) {
  auto* sb = static_cast<Sandbox*>(lua_touserdata(L, 1));
  lua_settop(L, 0);

  lua_createtable(L, 0, 0);
  lua_rawsetp(L, LUA_REGISTRYINDEX, &kModulesKey);
  lua_createtable(L, 0, 16);  // weak-keyed set of proxies
  lua_createtable(L, 0, 1);
  lua_pushliteral(L, "k");
  lua_setfield(L, -2, "__mode");
  lua_setmetatable(L, -2);
  lua_rawsetp(L, LUA_REGISTRYINDEX, &kReadOnlyKey);

  // base: opened into the state's original global table, then copied selectively.
  luaL_requiref(L, "_G", luaopen_base, 0);  // 1: original globals
  const int orig = lua_gettop(L);
  lua_createtable(L, 0, 40);  // 2: base (what the sandbox provides)
  const int base = lua_gettop(L);
  for (const char* name : {"assert", "error", "getmetatable", "ipairs", "next", "pairs",
                           "rawequal", "rawget", "rawlen", "select", "tonumber", "tostring",
                           "type", "_VERSION"}) {
    copy_field(L, orig, base, name);
  }
  const struct { const char* name; lua_CFunction fn; } wrappers[] = {
      {"pcall", sb_pcall},         {"xpcall", sb_xpcall},
      {"setmetatable", sb_setmetatable}, {"rawset", sb_rawset},
      {"collectgarbage", sb_collectgarbage}, {"print", sb_print},
      {"load", sb_load},           {"require", sb_require},
  };
  for (const auto& w : wrappers) {
    lua_pushcfunction(L, w.fn);
    lua_setfield(L, base, w.name);
  }

  // string: a guarded copy; the string metatable points at it.
  open_library(L, "string", luaopen_string);
  const int original_string = lua_gettop(L);
  lua_createtable(L, 0, 20);
  const int string_table = lua_gettop(L);
  for (const char* name : {"byte", "char", "format", "len", "lower", "pack", "packsize", "reverse",
                           "sub", "unpack", "upper"}) {
    copy_field(L, original_string, string_table, name);
  }
  install_safe_string(L, string_table, original_string);
  lua_pushvalue(L, string_table);  // real string table, kept for the metatable
  lua_pushvalue(L, string_table);
  make_read_only(L, "string");     // proxy
  lua_pushvalue(L, -1);
  lua_setfield(L, base, "string");
  // What getmetatable("") returns: a read-only view whose __index is the proxy.
  lua_createtable(L, 0, 1);
  lua_insert(L, -2);
  lua_setfield(L, -2, "__index");
  make_read_only(L, "string metatable");
  lua_createtable(L, 0, 2);  // the real metatable of strings
  lua_insert(L, -2);
  lua_setfield(L, -2, "__metatable");
  lua_insert(L, -2);
  lua_setfield(L, -2, "__index");
  lua_pushliteral(L, "");
  lua_insert(L, -2);
  lua_setmetatable(L, -2);
  lua_settop(L, base);

  // table, math, utf8: as they are, behind read-only proxies.
  const struct { const char* name; lua_CFunction open; } libraries[] = {
      {"table", luaopen_table}, {"math", luaopen_math}, {"utf8", luaopen_utf8}};
  for (const auto& lib : libraries) {
    open_library(L, lib.name, lib.open);
    make_read_only(L, lib.name);
    lua_setfield(L, base, lib.name);
  }

  // coroutine: resume/wrap/close re-raise a tripped budget.
  open_library(L, "coroutine", luaopen_coroutine);
  const int co = lua_gettop(L);
  lua_getfield(L, co, "resume");
  lua_pushcclosure(L, call_then_check, 1);
  lua_setfield(L, co, "resume");
  lua_getfield(L, co, "close");
  lua_pushcclosure(L, call_then_check, 1);
  lua_setfield(L, co, "close");
  lua_getfield(L, co, "wrap");
  lua_pushcclosure(L, sb_wrap, 1);
  lua_setfield(L, co, "wrap");
  make_read_only(L, "coroutine");
  lua_setfield(L, base, "coroutine");

  // os: time and dates only.
  open_library(L, "os", luaopen_os);
  const int os = lua_gettop(L);
  lua_createtable(L, 0, 4);
  for (const char* name : {"time", "date", "clock", "difftime"}) copy_field(L, os, os + 1, name);
  make_read_only(L, "os");
  lua_setfield(L, base, "os");
  lua_settop(L, base);

  // The skill's globals: its own table, reading through to `base`.
  lua_createtable(L, 0, 16);
  const int globals = lua_gettop(L);
  lua_createtable(L, 0, 3);
  lua_pushvalue(L, base);
  lua_setfield(L, -2, "__index");
  lua_pushvalue(L, base);
  lua_pushcclosure(L, globals_newindex, 1);
  lua_setfield(L, -2, "__newindex");
  lua_pushliteral(L, "locked");
  lua_setfield(L, -2, "__metatable");
  lua_setmetatable(L, globals);
  lua_pushvalue(L, globals);
  lua_setfield(L, base, "_G");
  lua_pushvalue(L, globals);
  lua_rawsetp(L, LUA_REGISTRYINDEX, &kGlobalsKey);
  lua_pushvalue(L, globals);
  lua_rawseti(L, LUA_REGISTRYINDEX, LUA_RIDX_GLOBALS);
  lua_pushvalue(L, base);
  lua_rawsetp(L, LUA_REGISTRYINDEX, &kBaseKey);

  // Forget the original library tables (package.loaded keeps them: empty it).
  lua_pushnil(L);
  lua_setfield(L, LUA_REGISTRYINDEX, LUA_LOADED_TABLE);
  lua_settop(L, 0);
  lua_gc(L, LUA_GCCOLLECT);
  (void)sb;
  return 0;
}

int Sandbox::protect(int (*fn)(lua_State*), void* ctx, std::string* error) {
  lua_State* L = L_;
  const int top = lua_gettop(L);
  lua_pushcfunction(L, fn);
  lua_pushlightuserdata(L, ctx);
  const int status = lua_pcall(L, 1, 0, 0);
  if (status != LUA_OK && error != nullptr) {
    const char* message = lua_type(L, -1) == LUA_TSTRING ? lua_tostring(L, -1) : nullptr;
    *error = message != nullptr ? message
                                : (status == LUA_ERRMEM ? "not enough memory" : "unknown error");
  }
  lua_settop(L, top);
  return status;
}

namespace {

// "name.lua:12: " or "(load):3: " at the start of a message.
bool has_position(std::string_view message) {
  const std::size_t colon = message.find(':');
  if (colon == std::string_view::npos || colon == 0) return false;
  for (std::size_t i = 0; i < colon; ++i) {
    if (message[i] == ' ' || message[i] == '\n') return false;
  }
  std::size_t i = colon + 1;
  const std::size_t digits = i;
  while (i < message.size() && message[i] >= '0' && message[i] <= '9') ++i;
  return i > digits && i < message.size() && message[i] == ':';
}

std::string position_of(lua_State* co) {
  lua_Debug ar;
  for (int level = 0; lua_getstack(co, level, &ar) != 0; ++level) {
    if (lua_getinfo(co, "Sl", &ar) == 0) break;
    if (ar.currentline > 0) return std::string(ar.short_src) + ":" + std::to_string(ar.currentline) + ": ";
  }
  return std::string();
}

}  // namespace

std::string Sandbox::describe_error(lua_State* co) const {
  std::string message;
  switch (lua_type(co, -1)) {
    case LUA_TSTRING: {
      std::size_t len = 0;
      const char* text = lua_tolstring(co, -1, &len);
      message.assign(text, len);
      break;
    }
    case LUA_TNUMBER: {
      char buffer[64];
      if (lua_isinteger(co, -1)) {
        std::snprintf(buffer, sizeof buffer, "%lld", static_cast<long long>(lua_tointeger(co, -1)));
      } else {
        std::snprintf(buffer, sizeof buffer, "%.14g", lua_tonumber(co, -1));
      }
      message = buffer;
      break;
    }
    case LUA_TNIL:
      message = "error raised with a nil error object";
      break;
    default:
      message = std::string("error object is a ") + luaL_typename(co, -1) +
                " value (raise errors with a string: error(\"what went wrong\"))";
      break;
  }
  if (tripped_) {
    std::string position;
    if (has_position(message)) {
      // Keep "file:line: " of the first position.
      const std::size_t colon = message.find(':', message.find(':') + 1);
      position = message.substr(0, colon + 2);
    } else {
      position = position_of(co);
    }
    return position + trip_reason_;
  }
  if (message == "not enough memory") message = "out of memory";
  if (!has_position(message)) message = position_of(co) + message;
  return message;
}

void Sandbox::load_file(lua_State* L, const char* relative) {
  // Phase 1, C++ only: find and read the file; results in members.
  scratch_error_.clear();
  scratch_source_.clear();
  try {
    namespace fs = std::filesystem;
    const std::string relative_name(relative);
    std::error_code ec;
    const fs::path root = fs::weakly_canonical(folder_, ec);
    const fs::path file = fs::weakly_canonical(folder_ / relative_name, ec);
    const auto [end, _] = std::mismatch(root.begin(), root.end(), file.begin(), file.end());
    if (ec || end != root.end()) {
      scratch_error_ = "'" + relative_name + "' is outside the skill's folder";
    } else if (!fs::is_regular_file(file, ec)) {
      scratch_error_ = "no file '" + relative_name + "' in the skill's folder";
    } else if (fs::file_size(file, ec) > limits_.source_bytes) {
      scratch_error_ = "'" + relative_name + "' is larger than " +
                       std::to_string(limits_.source_bytes / 1024) + " KB";
    } else {
      std::ifstream in(file, std::ios::binary);
      std::ostringstream text;
      text << in.rdbuf();
      if (!in.good() && !in.eof()) {
        scratch_error_ = "cannot read '" + relative_name + "'";
      } else {
        scratch_source_ = text.str();
      }
    }
    scratch_name_ = std::string("@") + relative;
  } catch (const std::exception& e) {
    scratch_error_ = std::string("cannot read '") + relative + "': " + e.what();
  }
  // Phase 2: Lua calls only.
  if (!scratch_error_.empty()) {
    luaL_error(L, "%s", scratch_error_.c_str());
    return;
  }
  const int status = luaL_loadbufferx(L, scratch_source_.data(), scratch_source_.size(),
                                      scratch_name_.c_str(), "t");
  scratch_source_.clear();
  scratch_source_.shrink_to_fit();
  if (status != LUA_OK) lua_error(L);
  push_globals(L);
  lua_setupvalue(L, -2, 1);
}

struct RunContext {
  Sandbox* sandbox;
  std::string_view code;
  const std::string* relative;  // run_file
  std::string chunkname;
  RunResult* result;
  int ref = LUA_NOREF;          // call
};

namespace {

int run_protected(lua_State* L) {
  auto* ctx = static_cast<RunContext*>(lua_touserdata(L, 1));
  Sandbox* sb = ctx->sandbox;
  lua_State* co = lua_newthread(L);
  int status = LUA_OK;
  int nargs = 0;
  if (ctx->ref != LUA_NOREF) {
    lua_rawgeti(co, LUA_REGISTRYINDEX, ctx->ref);
  } else if (ctx->relative != nullptr) {
    // Loading errors are errors of the file: run the loader inside the coroutine.
    lua_pushcfunction(co, [](lua_State* C) {
      Sandbox::from(C)->load_file(C, lua_tostring(C, 1));
      lua_call(C, 0, 0);
      return 0;
    });
    lua_pushstring(co, ctx->relative->c_str());
    nargs = 1;
  } else {
    status = luaL_loadbufferx(co, ctx->code.data(), ctx->code.size(), ctx->chunkname.c_str(), "t");
    if (status == LUA_OK) {
      sb->push_globals(co);
      lua_setupvalue(co, -2, 1);
    }
  }
  if (status == LUA_OK) {
    int results = 0;
    sb->enter_script();
    status = lua_resume(co, L, nargs, &results);
    sb->leave_script();
    if (status == LUA_ERRMEM) sb->trip(std::string());
    if (status == LUA_YIELD) {
      ctx->result->ok = false;
      try {
        ctx->result->error = "coroutine.yield() outside a coroutine";
      } catch (...) {
      }
      return 0;
    }
  }
  if (status != LUA_OK) {
    ctx->result->ok = false;
    try {
      ctx->result->error = sb->describe_error(co);
    } catch (...) {
      ctx->result->error.clear();
    }
  }
  return 0;
}

}  // namespace

// The body shared by run(), run_file() and call(): one coroutine under a fresh budget.
// `ctx.result` is where run_protected() reports; a trip's reason wins over the error it
// raised, because the raised error may have passed through the script's own handlers.
RunResult Sandbox::invoke(RunContext& ctx) {
  RunResult result;
  ctx.result = &result;
  try {
    begin_invocation();
    std::string error;
    if (protect(run_protected, &ctx, &error) != LUA_OK) {
      result.ok = false;
      result.error = tripped_ ? trip_reason_ : error;
    }
    result.tripped = tripped_;
    end_invocation();
  } catch (const std::exception& e) {
    result.ok = false;
    result.error = e.what();
  }
  return result;
}

RunResult Sandbox::run(std::string_view code, std::string_view chunkname) {
  try {
    RunContext ctx{this, code, nullptr, std::string(), nullptr, LUA_NOREF};
    const bool file = chunkname.size() > 4 && chunkname.substr(chunkname.size() - 4) == ".lua";
    ctx.chunkname.reserve(chunkname.size() + 1);
    ctx.chunkname.push_back(file ? '@' : '=');
    ctx.chunkname.append(chunkname);
    return invoke(ctx);
  } catch (const std::exception& e) {  // the chunk name did not fit in memory
    RunResult result;
    result.ok = false;
    result.error = e.what();
    return result;
  }
}

RunResult Sandbox::call(int ref) {
  RunContext ctx{this, {}, nullptr, std::string(), nullptr, ref};
  return invoke(ctx);
}

RunResult Sandbox::run_file(const std::string& relative) {
  RunContext ctx{this, {}, &relative, std::string(), nullptr, LUA_NOREF};
  return invoke(ctx);
}

}  // namespace marvin::scripting
