// JSON <-> Lua values, for slots and the Robot API's JSON calls.
//
//   JSON object  <-> table with string keys        JSON array <-> sequence 1..n
//   string, number (integers stay integers), true/false as themselves; null -> nil
//
// A Lua table converts to an array when its keys are exactly 1..n (an empty table is an
// object), otherwise to an object; keys must then be strings. Functions, coroutines and
// userdata do not convert. Nesting is limited to kMaxJsonDepth (cyclic tables are refused).
#pragma once

#include <string>

#include <nlohmann/json.hpp>

struct lua_State;

namespace marvin::scripting {

inline constexpr int kMaxJsonDepth = 32;

// Pushes `value`. May raise a Lua error (memory); call where that is safe: the caller's
// frame must not own C++ objects (see sandbox.cpp), so pass a value owned elsewhere.
void push_json(lua_State* L, const nlohmann::json& value);

// Converts the value at `index`. Never raises a Lua error and never throws; on failure
// returns false with a sentence in *error ("field 'at' is a function").
bool to_json(lua_State* L, int index, nlohmann::json* out, std::string* error);

}  // namespace marvin::scripting
