#include "scripting/lua_json.h"

#include <lua.hpp>

namespace marvin::scripting {
namespace {

void push_value(lua_State* L, const nlohmann::json& value, int depth) {
  if (depth > kMaxJsonDepth) luaL_error(L, "JSON nested too deeply");
  luaL_checkstack(L, 3, "JSON nested too deeply");
  switch (value.type()) {
    case nlohmann::json::value_t::object: {
      lua_createtable(L, 0, static_cast<int>(value.size()));
      for (auto it = value.begin(); it != value.end(); ++it) {
        const std::string& key = it.key();
        lua_pushlstring(L, key.data(), key.size());
        push_value(L, it.value(), depth + 1);
        lua_rawset(L, -3);
      }
      break;
    }
    case nlohmann::json::value_t::array: {
      lua_createtable(L, static_cast<int>(value.size()), 0);
      for (std::size_t i = 0; i < value.size(); ++i) {
        push_value(L, value[i], depth + 1);
        lua_rawseti(L, -2, static_cast<lua_Integer>(i + 1));
      }
      break;
    }
    case nlohmann::json::value_t::string: {
      const std::string& text = value.get_ref<const std::string&>();
      lua_pushlstring(L, text.data(), text.size());
      break;
    }
    case nlohmann::json::value_t::boolean:
      lua_pushboolean(L, value.get<bool>() ? 1 : 0);
      break;
    case nlohmann::json::value_t::number_integer:
      lua_pushinteger(L, static_cast<lua_Integer>(value.get<std::int64_t>()));
      break;
    case nlohmann::json::value_t::number_unsigned:
      lua_pushinteger(L, static_cast<lua_Integer>(value.get<std::uint64_t>()));
      break;
    case nlohmann::json::value_t::number_float:
      lua_pushnumber(L, value.get<double>());
      break;
    default:
      lua_pushnil(L);
      break;
  }
}

bool convert(lua_State* L, int index, nlohmann::json* out, std::string* error, int depth,
             const std::string& where) {
  index = lua_absindex(L, index);
  switch (lua_type(L, index)) {
    case LUA_TNIL:
      *out = nullptr;
      return true;
    case LUA_TBOOLEAN:
      *out = lua_toboolean(L, index) != 0;
      return true;
    case LUA_TNUMBER:
      if (lua_isinteger(L, index)) {
        *out = static_cast<std::int64_t>(lua_tointeger(L, index));
      } else {
        *out = lua_tonumber(L, index);
      }
      return true;
    case LUA_TSTRING: {
      std::size_t len = 0;
      const char* text = lua_tolstring(L, index, &len);
      *out = std::string(text, len);
      return true;
    }
    case LUA_TTABLE:
      break;
    default:
      *error = (where.empty() ? std::string("the value") : where) + " is a " + lua_typename(L, lua_type(L, index)) + " (not convertible to JSON)";
      return false;
  }
  if (depth >= kMaxJsonDepth || lua_checkstack(L, 3) == 0) {
    *error = (where.empty() ? std::string("the value") : where) +
             " is nested too deeply (or refers to itself)";
    return false;
  }
  const auto length = static_cast<std::size_t>(lua_rawlen(L, index));
  std::size_t count = 0;
  bool sequence = length > 0;
  lua_pushnil(L);
  while (lua_next(L, index) != 0) {
    ++count;
    if (!lua_isinteger(L, -2)) sequence = false;
    lua_pop(L, 1);
  }
  if (sequence && count == length) {
    *out = nlohmann::json::array();
    for (std::size_t i = 1; i <= length; ++i) {
      lua_rawgeti(L, index, static_cast<lua_Integer>(i));
      nlohmann::json item;
      const bool ok = convert(L, -1, &item, error, depth + 1, (where.empty() ? std::string("item") : where) + "[" + std::to_string(i) + "]");
      lua_pop(L, 1);
      if (!ok) return false;
      out->push_back(std::move(item));
    }
    return true;
  }
  *out = nlohmann::json::object();
  lua_pushnil(L);
  while (lua_next(L, index) != 0) {
    if (lua_type(L, -2) != LUA_TSTRING) {
      lua_pop(L, 2);
      *error = (where.empty() ? std::string("the table") : where) + " mixes list items and named fields (keys must all be names)";
      return false;
    }
    std::size_t len = 0;
    const char* key = lua_tolstring(L, -2, &len);
    std::string name(key, len);
    nlohmann::json item;
    const bool ok = convert(L, -1, &item, error, depth + 1,
                            where.empty() ? "field '" + name + "'" : where + "." + name);
    lua_pop(L, 1);
    if (!ok) {
      lua_pop(L, 1);
      return false;
    }
    (*out)[name] = std::move(item);
  }
  return true;
}

}  // namespace

void push_json(lua_State* L, const nlohmann::json& value) { push_value(L, value, 0); }

bool to_json(lua_State* L, int index, nlohmann::json* out, std::string* error) {
  const int top = lua_gettop(L);
  index = lua_absindex(L, index);
  try {
    const bool ok = convert(L, index, out, error, 0, std::string());
    lua_settop(L, top);
    return ok;
  } catch (const std::exception& e) {
    lua_settop(L, top);
    *error = e.what();
    return false;
  }
}

}  // namespace marvin::scripting
