// Guarded string functions for the sandbox.
//
// Lua's pattern matcher backtracks: string.find(("a"):rep(1e5), ("a*"):rep(20) .. "b") runs
// for hours inside one C call, where no instruction hook can stop it. The functions here
// are the standard find, match, gmatch and gsub with the same pattern language, plus a step
// counter: each call may take at most Limits::pattern_steps matching steps (and no more
// than the instruction budget has left; the steps are charged to it). rep and gsub refuse
// to build strings larger than Limits::string_bytes.
#pragma once

struct lua_State;

namespace marvin::scripting {

// Sets rep, find, match, gmatch and gsub in the table at `target`; `original` is the
// standard string library (rep delegates to it after the size check).
void install_safe_string(lua_State* L, int target, int original);

}  // namespace marvin::scripting
