// Lua skill figures (goals from the issue):
//   dispatch  intent -> Lua handler doing one marvin.say    goal < 20 us median
//   memory    an idle loaded skill                            goal < 100 KB
//   loading   50 Lua skills at start                          goal < 100 ms
// Baselines measured in the same run: the same dispatch into a C++ handler (what a native
// skill costs), a bare lua_State with Lua's standard libraries, and loading the same
// script 50 times into bare states. Prints figures; never fails on time.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include <lua.hpp>
#include <nlohmann/json.hpp>

#include "scripting/lua_skill.h"

namespace {

using Clock = std::chrono::steady_clock;
using marvin::scripting::LuaSkill;
using marvin::scripting::SkillSpec;

// A Robot API that does nothing: the figures are the runtime's own cost.
struct NullRobot {
  static const marvin_robot_api* api() {
    static const marvin_robot_api table = [] {
      marvin_robot_api t{};
      t.struct_size = sizeof(marvin_robot_api);
      t.major = MARVIN_ROBOT_API_MAJOR;
      t.minor = MARVIN_ROBOT_API_MINOR;
      t.last_error = [](marvin_host*) { return ""; };
      t.say = [](marvin_host*, const char*) { return MARVIN_OK; };
      t.ask = [](marvin_host*, const char*, marvin_text_out* out) {
        out->length = 0;
        if (out->capacity > 0) out->data[0] = '\0';
        return MARVIN_OK;
      };
      t.now = [](marvin_host*, std::int64_t* ms) {
        *ms = 1767603600000;
        return MARVIN_OK;
      };
      t.storage_get = [](marvin_host*, const char*, marvin_text_out*) { return MARVIN_ERR_NOT_FOUND; };
      t.storage_set = [](marvin_host*, const char*, const char*, size_t) { return MARVIN_OK; };
      t.log = [](marvin_host*, marvin_log_level, const char*) { return MARVIN_OK; };
      t.is_cancelled = [](marvin_host*) { return 0; };
      return t;
    }();
    return &table;
  }
};

double median_us(std::vector<double> samples) {
  std::sort(samples.begin(), samples.end());
  return samples[samples.size() / 2];
}

double percentile_us(std::vector<double> samples, double p) {
  std::sort(samples.begin(), samples.end());
  return samples[static_cast<std::size_t>(p * static_cast<double>(samples.size() - 1))];
}

double us_since(Clock::time_point start) {
  return std::chrono::duration<double, std::micro>(Clock::now() - start).count();
}

SkillSpec hello_spec(const std::string& id) {
  return SkillSpec{id, MARVIN_LUA_EXAMPLE_DIR, "main.lua", {"hello", "about", "my_name"}, {"storage"}};
}

void dispatch() {
  SkillSpec spec = hello_spec("hello-lua");
  LuaSkill skill(spec, NullRobot::api(), nullptr);
  const marvin_request request{sizeof(marvin_request), "about", "{}", "who are you"};
  constexpr int kRuns = 20000;
  std::string error;
  for (int i = 0; i < 1000; ++i) skill.handle(request, &error);  // warm up
  std::vector<double> lua_us;
  lua_us.reserve(kRuns);
  for (int i = 0; i < kRuns; ++i) {
    const auto start = Clock::now();
    if (skill.handle(request, &error) != MARVIN_OK) {
      std::printf("dispatch failed: %s\n", error.c_str());
      return;
    }
    lua_us.push_back(us_since(start));
  }
  // Baseline: the same request handled by C++ (parse the slots, one say).
  const marvin_robot_api* api = NullRobot::api();
  std::vector<double> native_us;
  native_us.reserve(kRuns);
  for (int i = 0; i < kRuns; ++i) {
    const auto start = Clock::now();
    const nlohmann::json slots = nlohmann::json::parse(request.slots_json);
    if (std::strcmp(request.intent, "about") == 0 && slots.is_object()) {
      api->say(nullptr, "I am Marvin, a home robot.");
    }
    native_us.push_back(us_since(start));
  }
  const double lua = median_us(lua_us);
  const double native = median_us(native_us);
  std::printf("dispatch: intent -> Lua handler with one marvin.say: median %.2f us, p99 %.2f us "
              "(goal < 20 us)\n", lua, percentile_us(lua_us, 0.99));
  std::printf("          baseline C++ handler (parse slots + say): median %.3f us; Lua/C++ = %.1fx\n",
              native, lua / native);
}

std::size_t bare_state_bytes(const std::string& script) {
  struct Counter {
    std::size_t bytes = 0;
  } counter;
  lua_State* L = lua_newstate(
      [](void* ud, void* ptr, std::size_t osize, std::size_t nsize) -> void* {
        auto* c = static_cast<Counter*>(ud);
        const std::size_t old = ptr != nullptr ? osize : 0;
        if (nsize == 0) {
          std::free(ptr);
          c->bytes -= old;
          return nullptr;
        }
        void* block = std::realloc(ptr, nsize);
        if (block != nullptr) c->bytes = c->bytes - old + nsize;
        return block;
      },
      &counter);
  luaL_openlibs(L);
  if (!script.empty()) {
    // The example's main.lua needs `marvin`: give it a stub table.
    luaL_dostring(L, "marvin = {on = function() end, say = function() end}");
    luaL_dostring(L, script.c_str());
  }
  lua_gc(L, LUA_GCCOLLECT);
  const std::size_t bytes = counter.bytes;
  lua_close(L);
  return bytes;
}

std::string read_main() {
  std::string text;
  if (FILE* f = std::fopen(MARVIN_LUA_EXAMPLE_DIR "/main.lua", "rb")) {
    char buffer[4096];
    std::size_t n = 0;
    while ((n = std::fread(buffer, 1, sizeof buffer, f)) > 0) text.append(buffer, n);
    std::fclose(f);
  }
  return text;
}

void memory() {
  SkillSpec spec = hello_spec("hello-lua");
  LuaSkill skill(spec, NullRobot::api(), nullptr);
  const std::size_t idle = skill.memory_bytes();  // loaded, waiting for its first request
  const marvin_request request{sizeof(marvin_request), "about", "{}", "who are you"};
  std::string error;
  for (int i = 0; i < 1000; ++i) skill.handle(request, &error);
  const std::size_t after = skill.memory_bytes();  // garbage not yet collected included
  const std::size_t bare = bare_state_bytes("");
  const std::size_t bare_script = bare_state_bytes(read_main());
  std::printf("memory: idle loaded skill (hello example): %.1f KB (goal < 100 KB); after 1000 "
              "requests: %.1f KB\n", static_cast<double>(idle) / 1024.0,
              static_cast<double>(after) / 1024.0);
  std::printf("        baseline bare lua_State + standard libraries: %.1f KB; with the same "
              "script: %.1f KB; sandbox/bare = %.2fx\n",
              static_cast<double>(bare) / 1024.0, static_cast<double>(bare_script) / 1024.0,
              static_cast<double>(idle) / static_cast<double>(bare_script));
}

void loading() {
  constexpr int kSkills = 50;
  std::vector<double> lua_ms;
  std::vector<double> bare_ms;
  const std::string script = read_main();
  for (int round = 0; round < 5; ++round) {
    std::vector<std::unique_ptr<LuaSkill>> skills;
    const auto start = Clock::now();
    for (int i = 0; i < kSkills; ++i) {
      skills.push_back(std::make_unique<LuaSkill>(hello_spec("hello-" + std::to_string(i)),
                                                  NullRobot::api(), nullptr));
    }
    lua_ms.push_back(us_since(start) / 1000.0);
    const auto bare_start = Clock::now();
    std::vector<lua_State*> states;
    for (int i = 0; i < kSkills; ++i) {
      lua_State* L = luaL_newstate();
      luaL_openlibs(L);
      luaL_dostring(L, "marvin = {on = function() end, say = function() end}");
      luaL_dostring(L, script.c_str());
      states.push_back(L);
    }
    bare_ms.push_back(us_since(bare_start) / 1000.0);
    for (lua_State* L : states) lua_close(L);
  }
  const double lua = median_us(lua_ms);
  const double bare = median_us(bare_ms);
  std::printf("loading: 50 Lua skills (sandbox + API + main.lua from disk): median %.2f ms "
              "(goal < 100 ms)\n", lua);
  std::printf("         baseline 50 bare states + openlibs + the same script: %.2f ms; "
              "ratio %.1fx\n", bare, lua / bare);
}

}  // namespace

int main() {
  dispatch();
  memory();
  loading();
  return 0;
}
