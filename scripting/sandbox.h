// The Lua sandbox: one lua_State per skill, built from an allowlist, with budgets a script
// cannot escape.
//
// What a script sees (everything else is absent):
//   base       assert error getmetatable ipairs next pairs pcall print rawequal rawget rawlen
//              rawset select setmetatable tonumber tostring type xpcall _G _VERSION
//              collectgarbage ("collect", "count", "step", "isrunning" only)
//              load (text chunks given as strings only; the skill's environment by default)
//              require (only NAME.lua files inside the skill's own folder, as text)
//   string     without dump; rep, find, match, gmatch and gsub are guarded (see Limits)
//   table, math, utf8, coroutine
//   os         time, date, clock, difftime
// No io, debug, package, dofile, loadfile, warn, string.dump.
//
// Read-only: the library tables, the string metatable and any table made read-only with
// make_read_only() (the `marvin` API) are empty proxies; writing to them, rawset() on them
// or setmetatable() on them raises "attempt to modify read-only table 'NAME'". Globals that
// belong to the sandbox (print, string, marvin, ...) cannot be replaced; a skill defines
// its own globals freely.
//
// Budgets, per invocation (begin_invocation() .. end_invocation()):
//   - memory: the allocator refuses to grow the state beyond Limits::memory_bytes;
//   - instructions: a count hook charges every Lua instruction (and every pattern-matching
//     step) to one budget shared by all coroutines of the state;
//   - wall clock: checked by the same hook against Limits::wall_time, measured with the
//     injectable Clock; time spent waiting for the user (pause_clock()) does not count.
// When a budget trips, the state is "tripped": the running line errors, and so does every
// further instruction, pcall/xpcall return and coroutine resume until the call unwinds to
// the host. A tripped state should be discarded and rebuilt (LuaSkill does that).
//
// __gc metamethods are refused by setmetatable(): Lua runs finalizers with hooks disabled,
// so no budget could stop one that never ends.
//
// Threading: a Sandbox is used by one thread at a time.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <string_view>

#include "common/log.h"

struct lua_State;

namespace marvin::scripting {

// Budgets of one skill. The defaults suit a Raspberry Pi 3 class robot: a handler that
// answers a question uses well under 1% of each.
struct Limits {
  std::size_t memory_bytes = 4u << 20;          // whole state, 4 MB
  std::uint64_t instructions = 20'000'000;      // per invocation (about 0.1-0.5 s of Lua)
  std::chrono::milliseconds wall_time{2000};    // per invocation, user's thinking excluded
  std::size_t string_bytes = 1u << 20;          // largest string rep()/gsub() may build
  std::uint64_t pattern_steps = 2'000'000;      // per find/match/gmatch/gsub call
  std::size_t output_bytes = 8u << 10;          // print + marvin.log per invocation
  std::size_t source_bytes = 1u << 20;          // largest .lua file require() reads
};

// The clock the wall-time budget is measured with. Tests inject a fake one.
using Clock = std::function<std::chrono::steady_clock::time_point()>;

// Where print() output goes (after the output cap). Default: marvin::log with component
// "skill:<name>".
using OutputSink = std::function<void(LogLevel level, std::string_view text)>;

// The outcome of running script code.
struct RunResult {
  bool ok = true;
  bool tripped = false;   // a budget tripped: rebuild the state before using it again
  std::string error;      // "main.lua:3: message" (the position of the script's line)
};

// What one run(), run_file() or call() executes (defined in sandbox.cpp).
struct RunContext;

class Sandbox {
 public:
  // Builds the state. `name` is the skill id (used in messages), `folder` the skill's folder
  // (what require() may read). Throws std::runtime_error if the state cannot be built.
  Sandbox(std::string name, std::filesystem::path folder, Limits limits = {}, Clock clock = {});
  ~Sandbox();
  Sandbox(const Sandbox&) = delete;
  Sandbox& operator=(const Sandbox&) = delete;

  lua_State* state() const { return L_; }
  const std::string& name() const { return name_; }
  const std::filesystem::path& folder() const { return folder_; }
  const Limits& limits() const { return limits_; }

  // The Sandbox owning `L` (any coroutine of it).
  static Sandbox* from(lua_State* L);

  // Something the host attaches (LuaSkill attaches itself).
  void set_owner(void* owner) { owner_ = owner; }
  void* owner() const { return owner_; }

  void set_output(OutputSink sink) { output_ = std::move(sink); }
  // Asked at every budget check (every kHookInterval instructions); when it answers true
  // the state trips with "cancelled" (the user said "stop").
  void set_cancel_check(std::function<bool()> check) { cancel_ = std::move(check); }
  bool cancelled() const { return cancelled_; }

  // --- budgets ---------------------------------------------------------------------------
  // Starts a fresh budget: instruction count 0, deadline now + wall_time, output 0. Clears a
  // previous trip (the caller decides whether to keep a tripped state).
  void begin_invocation();
  void end_invocation();
  // Stops / restarts the wall clock (while the user thinks about a question).
  void pause_clock();
  void resume_clock();
  bool tripped() const { return tripped_; }
  const std::string& trip_reason() const { return trip_reason_; }
  std::uint64_t instructions_used() const { return instructions_; }
  // Charges `steps` to the instruction budget (pattern matching); trips and raises when the
  // budget or the deadline is exhausted. Call from Lua C functions only.
  void charge(lua_State* L, std::uint64_t steps);
  // Raises the trip error in `L` and makes every further instruction of `L` error.
  [[noreturn]] void raise_tripped(lua_State* L);
  // Bytes the state currently holds.
  std::size_t memory_used() const { return memory_used_; }

  // Appends `text` to the output under the cap; returns false once the cap is reached (the
  // first refusal logs one notice).
  bool emit(LogLevel level, std::string_view text);

  // --- running code (from the host, not from inside Lua) ------------------------------------
  // Compiles `code` (text only) as chunk `chunkname` ("main.lua" -> errors "main.lua:LINE:")
  // in the skill's environment and runs it in a coroutine under a fresh budget. Yields are
  // refused. Never throws.
  RunResult run(std::string_view code, std::string_view chunkname);
  // Reads `relative` from the skill's folder and runs it like run(). Never throws.
  RunResult run_file(const std::string& relative);
  // Calls the function stored in the registry under `ref` (luaL_ref) with no arguments,
  // like run(). Never throws.
  RunResult call(int ref);

  // --- helpers for bindings (call from Lua C functions or protected host code) ---------------
  // Pushes the skill's global table.
  void push_globals(lua_State* L) const;
  // Pops a table and pushes a read-only proxy of it named `name` (for error messages).
  static void make_read_only(lua_State* L, const char* name);
  // Declares a global that scripts may read but not replace (pops the value).
  void set_protected_global(lua_State* L, const char* name);
  // Runs `fn(L, ctx)` in protected mode on the main state; returns the Lua status and puts
  // an error message into *error. Use for host-side work on the state so that a memory
  // error never reaches Lua's panic handler.
  int protect(int (*fn)(lua_State*), void* ctx, std::string* error);
  // Describes the error value on top of coroutine `co` ("main.lua:3: message"), adding the
  // position of the innermost script line when the message has none. Never calls script
  // code (__tostring is ignored). Does not pop.
  std::string describe_error(lua_State* co) const;
  // Loads a text chunk read from the skill's folder; pushes the function or raises.
  void load_file(lua_State* L, const char* relative);

  // Script-facing hooks (public so the C callbacks in sandbox.cpp can reach them).
  void note_refusal(std::size_t size);
  bool script_running() const { return script_depth_ > 0; }
  void enter_script() { ++script_depth_; }
  void leave_script() { --script_depth_; }
  void trip(const std::string& reason) noexcept;
  void check_budget(lua_State* L, std::uint64_t count);
  bool over_budget(std::uint64_t count) noexcept;
  std::uint64_t instructions_left() const {
    return instructions_ >= limits_.instructions ? 0 : limits_.instructions - instructions_;
  }

 private:
  RunResult invoke(RunContext& ctx);
  static void* allocate(void* ud, void* ptr, std::size_t old_size, std::size_t new_size);
  static int setup(lua_State* L);

  std::string name_;
  std::filesystem::path folder_;
  Limits limits_;
  Clock clock_;
  OutputSink output_;
  std::function<bool()> cancel_;
  bool cancelled_ = false;
  void* owner_ = nullptr;
  lua_State* L_ = nullptr;

  std::size_t memory_used_ = 0;
  std::size_t refused_size_ = 0;
  int script_depth_ = 0;

  std::uint64_t instructions_ = 0;
  std::chrono::steady_clock::time_point deadline_{};
  std::chrono::steady_clock::time_point paused_at_{};
  bool paused_ = false;
  bool tripped_ = false;
  std::string trip_reason_;
  std::size_t output_used_ = 0;
  bool output_capped_ = false;

  // Text computed by C++ code inside Lua C functions lives here, not in locals (see sandbox.cpp).
  std::string scratch_source_;
  std::string scratch_name_;
  std::string scratch_error_;
};

// How often the count hook runs (instructions between checks).
inline constexpr int kHookInterval = 1000;

}  // namespace marvin::scripting
