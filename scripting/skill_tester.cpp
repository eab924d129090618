#include "scripting/skill_tester.h"

#include <algorithm>
#include <deque>
#include <memory>
#include <optional>
#include <stdexcept>

#include <lua.hpp>

#include "common/log.h"
#include "scripting/lua_json.h"
#include "skills/scripted_eyes.h"
#include "scripting/lua_runtime.h"
#include "scripting/sandbox.h"
#include "skills/api_json.h"
#include "skills/in_memory_personal_data.h"
#include "skills/manager.h"
#include "skills/registry.h"

namespace marvin::scripting {
namespace {

constexpr std::int64_t kStartMs = 1767603600000;  // 2026-01-05T09:00:00Z, a Monday

// The simulated robot of one test: the host's registry and manager over a recording body
// and a scripted user.
class TestWorld : public devices::Body, public skills::User {
 public:
  explicit TestWorld(const std::filesystem::path& skill_dir) {
    services_.data = &data_;
    services_.body = this;
    services_.user = this;
    services_.now_ms = [this] { return now_ms; };
    services_.time_zone = "UTC";
    services_.wait_for_motion = false;
    services_.sightings = &sightings_;
    services_.events = [this](std::string_view kind, std::int64_t since) {
      std::vector<skills::HostServices::LoggedEvent> out;
      for (auto it = events_.rbegin(); it != events_.rend(); ++it) {
        if (it->time_ms >= since && (kind.empty() || it->kind == kind)) out.push_back(*it);
      }
      return out;
    };
    registry_ = std::make_unique<skills::Registry>(services_);
    registry_->add_runtime(std::make_unique<LuaRuntime>());
    skills::ManagerOptions options;
    options.run_long_inline = true;
    manager_ = std::make_unique<skills::Manager>(*registry_, *this, options);
    services_.user = manager_.get();
    registry_->load_skill(skill_dir);
    if (!registry_->errors().empty()) load_error = registry_->errors().front().message;
    if (registry_->skills().size() == 1) skill_id = registry_->skills().front()->manifest.id;
  }
  ~TestWorld() override {
    manager_.reset();
    registry_.reset();
  }

  // devices::Body
  void move(devices::Direction direction, std::uint8_t speed,
            std::chrono::milliseconds duration) override {
    actions.push_back(std::string("move ") + devices::to_string(direction) + " speed=" +
                      std::to_string(speed) + " ms=" + std::to_string(duration.count()));
  }
  void stop() override { actions.emplace_back("stop"); }
  void tilt_head(int degrees) override { actions.push_back("tilt_head " + std::to_string(degrees)); }
  std::vector<devices::ScanPoint> latest_scan() override { return {}; }
  void set_light(devices::Light light) override {
    lights.emplace_back(devices::to_string(light));
  }

  // skills::User
  void say(std::string_view text) override { said.emplace_back(text); }
  std::optional<std::string> ask(std::string_view question) override {
    said.emplace_back(question);
    asked.emplace_back(question);
    if (answers.empty()) return std::nullopt;
    std::string answer = std::move(answers.front());
    answers.pop_front();
    return answer;
  }

  // One utterance; returns the index in said() where this turn starts.
  void utter(std::string_view utterance) {
    turn_said = said.size();
    turn_asked = asked.size();
    manager_->handle(utterance);
  }

  // Moves the clock and runs the skill's due marvin.after() timers.
  void advance(std::int64_t ms) {
    turn_said = said.size();
    turn_asked = asked.size();
    now_ms += ms;
    for (const auto& skill : registry_->skills()) {
      if (auto* lua = dynamic_cast<LuaSkillInstance*>(skill->instance.get())) {
        std::string error;
        if (lua->skill().run_due_timers(now_ms, &error) != MARVIN_OK) {
          marvin::log(LogLevel::kError, "skill:" + skill->manifest.id, error);
        }
      }
    }
  }

  std::string intent_of(std::string_view utterance) const {
    auto match = registry_->interpreter().match(utterance, manager_->context());
    return match ? match->intent : std::string();
  }

  std::optional<std::string> stored(const std::string& key) {
    return data_.storage_get(skill_id, key);
  }

  std::vector<std::string> reminders() {
    std::vector<std::string> out;
    for (const auto& r : data_.reminders_between(std::numeric_limits<std::int64_t>::min(),
                                                 std::numeric_limits<std::int64_t>::max())) {
      out.push_back(skills::reminder_to_json(r).dump());
    }
    return out;
  }

  std::int64_t add_contact(const std::string& name, const std::string& phone) {
    data::Contact contact;
    contact.name = name;
    if (!phone.empty()) contact.phone_numbers.push_back(phone);
    return data_.add_contact(contact);
  }

  // The scripted camera (robot.camera / robot.camera_fails); none until a test sets one.
  void set_camera(const std::string& seen_json) {
    eyes_.set_view(seen_json);
    services_.eyes = &eyes_;
  }
  // Finding (API 1.3): an event in the owner's log (robot.event); sightings in memory.
  void add_event(const std::string& kind, const std::string& message) {
    events_.push_back({kind, message, now_ms});
  }
  void camera_fails(const std::string& message) {
    eyes_.set_failure(message);
    services_.eyes = &eyes_;
  }
  const std::vector<std::string>& enrolled_faces() const { return eyes_.enrolled(); }

  std::string load_error;
  std::string skill_id;
  std::int64_t now_ms = kStartMs;
  std::deque<std::string> answers;
  std::vector<std::string> said, asked, actions, lights;
  std::size_t turn_said = 0;
  std::size_t turn_asked = 0;

 private:
  skills::InMemoryPersonalData data_;
  skills::ScriptedEyes eyes_{[this](std::string action) { actions.push_back(std::move(action)); }};
  skills::HostServices services_;
  skills::InMemorySightingLog sightings_{[this] { return now_ms; }};
  std::vector<skills::HostServices::LoggedEvent> events_;
  std::unique_ptr<skills::Registry> registry_;
  std::unique_ptr<skills::Manager> manager_;
};

// The Lua side of the tests. Written in Lua so failures point at the test's line
// (error(..., 2)).
const char* kPrelude = R"lua(
local function quote(list)
  if #list == 0 then return "nothing" end
  local parts = {}
  for i, s in ipairs(list) do parts[i] = string.format("%q", s) end
  return table.concat(parts, ", ")
end

function test(name, fn)
  if type(name) ~= "string" or type(fn) ~= "function" then
    error("usage: test(\"name\", function() ... end)", 2)
  end
  robot.register(name, fn)
end

function say(utterance) return robot.say(utterance) end
function answer(...) robot.answer(...) end

expect = {}
function expect.said(text)
  local turn = robot.turn()
  for _, s in ipairs(turn) do if s == text then return end end
  error(string.format("expected Marvin to say %q; it said %s", text, quote(turn)), 2)
end
function expect.said_like(pattern)
  local turn = robot.turn()
  for _, s in ipairs(turn) do if s:find(pattern) then return end end
  error(string.format("expected Marvin to say something like %q; it said %s", pattern, quote(turn)), 2)
end
function expect.not_said(text)
  for _, s in ipairs(robot.turn()) do
    if s == text then error(string.format("expected Marvin not to say %q", text), 2) end
  end
end
function expect.asked(text)
  local turn = robot.turn_asked()
  for _, s in ipairs(turn) do if s == text then return end end
  error(string.format("expected Marvin to ask %q; it asked %s", text, quote(turn)), 2)
end
function expect.did(action)
  local actions = robot.actions()
  for _, a in ipairs(actions) do if a == action then return end end
  error(string.format("expected the robot to do %q; it did %s", action, quote(actions)), 2)
end
function expect.stored(key, value)
  local actual = robot.stored(key)
  if actual ~= value then
    error(string.format("expected storage[%q] to be %s; it is %s", key,
      value == nil and "nil" or string.format("%q", value),
      actual == nil and "nil" or string.format("%q", actual)), 2)
  end
end
function expect.reminders(count)
  local n = #robot.reminders()
  if n ~= count then error(string.format("expected %d reminder(s); there are %d", count, n), 2) end
end
function expect.equal(actual, expected, what)
  if actual ~= expected then
    error(string.format("%sexpected %s; got %s", what and (what .. ": ") or "",
      tostring(expected), tostring(actual)), 2)
  end
end
function expect.truthy(value, what)
  if not value then error((what or "value") .. " is " .. tostring(value), 2) end
end
)lua";

struct Tester {
  std::filesystem::path skill_dir;
  std::unique_ptr<TestWorld> world;
  std::vector<std::pair<std::string, int>> registered;  // name, registry ref
};

Tester* tester_of(lua_State* L) {
  return static_cast<Tester*>(lua_touserdata(L, lua_upvalueindex(1)));
}

TestWorld& world_of(lua_State* L) {
  Tester* t = tester_of(L);
  if (!t->world) luaL_error(L, "the robot exists only inside a test(...) function");
  return *t->world;
}

void push_strings(lua_State* L, const std::vector<std::string>& list, std::size_t from) {
  lua_createtable(L, static_cast<int>(list.size() - std::min(from, list.size())), 0);
  lua_Integer i = 1;
  for (std::size_t k = from; k < list.size(); ++k) {
    lua_pushlstring(L, list[k].data(), list[k].size());
    lua_rawseti(L, -2, i++);
  }
}

int t_register(lua_State* L) {
  Tester* t = tester_of(L);
  const char* name = luaL_checkstring(L, 1);
  luaL_checktype(L, 2, LUA_TFUNCTION);
  lua_pushvalue(L, 2);
  const int ref = luaL_ref(L, LUA_REGISTRYINDEX);
  bool ok = true;
  try {
    t->registered.emplace_back(name, ref);
  } catch (...) {
    ok = false;
  }
  if (!ok) return luaL_error(L, "out of memory");
  return 0;
}

// The robot's functions run host code (the manager, the skill): they must not throw into
// Lua. Exceptions become a message in this buffer, raised after the C++ frame is gone.
thread_local std::string g_host_error;

template <typename Fn>
bool host_call(Fn fn) noexcept {
  try {
    fn();
    return true;
  } catch (const std::exception& e) {
    try {
      g_host_error = e.what();
    } catch (...) {
    }
    return false;
  }
}

int t_say(lua_State* L) {
  TestWorld& w = world_of(L);
  const char* utterance = luaL_checkstring(L, 1);
  if (!host_call([&] { w.utter(utterance); })) return luaL_error(L, "%s", g_host_error.c_str());
  push_strings(L, w.said, w.turn_said);
  return 1;
}

int t_answer(lua_State* L) {
  TestWorld& w = world_of(L);
  const int n = lua_gettop(L);
  for (int i = 1; i <= n; ++i) luaL_checkstring(L, i);
  for (int i = 1; i <= n; ++i) {
    const char* text = lua_tostring(L, i);
    if (!host_call([&] { w.answers.emplace_back(text); })) return luaL_error(L, "out of memory");
  }
  return 0;
}

int t_turn(lua_State* L) {
  TestWorld& w = world_of(L);
  push_strings(L, w.said, w.turn_said);
  return 1;
}

int t_turn_asked(lua_State* L) {
  TestWorld& w = world_of(L);
  push_strings(L, w.asked, w.turn_asked);
  return 1;
}

int t_said(lua_State* L) {
  push_strings(L, world_of(L).said, 0);
  return 1;
}

int t_actions(lua_State* L) {
  push_strings(L, world_of(L).actions, 0);
  return 1;
}

int t_stored(lua_State* L) {
  TestWorld& w = world_of(L);
  const char* key = luaL_checkstring(L, 1);
  static thread_local std::optional<std::string> result;  // not a local: see sandbox.cpp
  if (!host_call([&] { result = w.stored(key); })) return luaL_error(L, "%s", g_host_error.c_str());
  if (!result.has_value()) {
    lua_pushnil(L);
  } else {
    lua_pushlstring(L, result->data(), result->size());
  }
  return 1;
}

int t_reminders(lua_State* L) {
  TestWorld& w = world_of(L);
  static thread_local nlohmann::json result;
  if (!host_call([&] {
        result = nlohmann::json::array();
        for (const auto& text : w.reminders()) result.push_back(nlohmann::json::parse(text));
      })) {
    return luaL_error(L, "%s", g_host_error.c_str());
  }
  push_json(L, result);
  return 1;
}

int t_advance(lua_State* L) {
  TestWorld& w = world_of(L);
  const lua_Number seconds = luaL_checknumber(L, 1);
  luaL_argcheck(L, seconds >= 0, 1, "seconds must not be negative");
  if (!host_call([&] { w.advance(static_cast<std::int64_t>(seconds * 1000.0)); })) {
    return luaL_error(L, "%s", g_host_error.c_str());
  }
  push_strings(L, w.said, w.turn_said);
  return 1;
}

int t_now(lua_State* L) {
  lua_pushinteger(L, world_of(L).now_ms / 1000);
  return 1;
}

int t_set_now(lua_State* L) {
  TestWorld& w = world_of(L);
  w.now_ms = luaL_checkinteger(L, 1) * 1000;
  return 0;
}

int t_add_contact(lua_State* L) {
  TestWorld& w = world_of(L);
  const char* name = luaL_checkstring(L, 1);
  const char* phone = luaL_optstring(L, 2, "");
  std::int64_t id = 0;
  if (!host_call([&] { id = w.add_contact(name, phone); })) {
    return luaL_error(L, "%s", g_host_error.c_str());
  }
  lua_pushinteger(L, id);
  return 1;
}

// robot.camera(json_text): what the camera sees from now on (marvin.vision.look's JSON).
int t_camera(lua_State* L) {
  TestWorld& w = world_of(L);
  const char* view = luaL_checkstring(L, 1);
  if (!host_call([&] { w.set_camera(view); })) return luaL_error(L, "%s", g_host_error.c_str());
  return 0;
}

int t_camera_fails(lua_State* L) {
  TestWorld& w = world_of(L);
  const char* message = luaL_checkstring(L, 1);
  if (!host_call([&] { w.camera_fails(message); })) {
    return luaL_error(L, "%s", g_host_error.c_str());
  }
  return 0;
}

int t_event(lua_State* L) {
  TestWorld& w = world_of(L);
  const char* kind = luaL_checkstring(L, 1);
  const char* message = luaL_checkstring(L, 2);
  w.add_event(kind, message);
  return 0;
}

int t_faces(lua_State* L) {
  push_strings(L, world_of(L).enrolled_faces(), 0);
  return 1;
}

int t_intent(lua_State* L) {
  TestWorld& w = world_of(L);
  const char* utterance = luaL_checkstring(L, 1);
  static thread_local std::string result;
  if (!host_call([&] { result = w.intent_of(utterance); })) {
    return luaL_error(L, "%s", g_host_error.c_str());
  }
  if (result.empty()) {
    lua_pushnil(L);
  } else {
    lua_pushlstring(L, result.data(), result.size());
  }
  return 1;
}

int install_robot(lua_State* L) {
  auto* tester = static_cast<Tester*>(lua_touserdata(L, 1));
  static const luaL_Reg functions[] = {
      {"register", t_register}, {"say", t_say},           {"answer", t_answer},
      {"turn", t_turn},         {"turn_asked", t_turn_asked}, {"said", t_said},
      {"actions", t_actions},   {"stored", t_stored},     {"reminders", t_reminders},
      {"advance", t_advance},   {"now", t_now},           {"set_now", t_set_now},
      {"add_contact", t_add_contact}, {"intent", t_intent}, {"camera", t_camera},
      {"camera_fails", t_camera_fails}, {"faces", t_faces}, {"event", t_event},
      {nullptr, nullptr}};
  lua_createtable(L, 0, 16);
  lua_pushlightuserdata(L, tester);
  luaL_setfuncs(L, functions, 1);
  Sandbox::make_read_only(L, "robot");
  Sandbox::from(L)->set_protected_global(L, "robot");
  return 0;
}

std::vector<std::filesystem::path> test_files(const std::filesystem::path& skill_dir) {
  std::vector<std::filesystem::path> files;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(skill_dir / "tests", ec)) {
    if (entry.is_regular_file() && entry.path().extension() == ".lua") files.push_back(entry.path());
  }
  std::sort(files.begin(), files.end());
  return files;
}

}  // namespace

int TestReport::passed() const {
  return static_cast<int>(std::count_if(tests.begin(), tests.end(),
                                        [](const TestOutcome& t) { return t.passed; }));
}

int TestReport::failed() const {
  return static_cast<int>(tests.size()) - passed() + static_cast<int>(errors.size());
}

TestReport run_skill_tests(const std::filesystem::path& skill_dir,
                           const std::function<void(std::string_view)>& progress) {
  TestReport report;
  const auto files = test_files(skill_dir);
  if (files.empty()) {
    report.errors.push_back((skill_dir / "tests").string() + ": no *.lua test files");
    return report;
  }
  Limits limits;
  limits.memory_bytes = 16u << 20;
  limits.instructions = 200'000'000;
  limits.wall_time = std::chrono::seconds(30);
  limits.output_bytes = 64u << 10;
  for (const auto& file : files) {
    const std::string relative = "tests/" + file.filename().string();
    Tester tester;
    tester.skill_dir = skill_dir;
    std::vector<std::string> output;
    Sandbox sandbox("tests", skill_dir, limits);
    sandbox.set_output([&output](LogLevel, std::string_view text) { output.emplace_back(text); });
    std::string error;
    RunResult loaded;
    if (sandbox.protect(install_robot, &tester, &error) != LUA_OK) {
      loaded.ok = false;
      loaded.error = error;
    } else {
      loaded = sandbox.run(kPrelude, "expect");
      if (loaded.ok) loaded = sandbox.run_file(relative);
    }
    if (!loaded.ok) {
      report.errors.push_back(loaded.error);
      if (progress) progress("ERROR " + loaded.error);
      continue;
    }
    for (const auto& [name, ref] : tester.registered) {
      TestOutcome outcome;
      outcome.file = relative;
      outcome.name = name;
      std::vector<std::string> log;
      LogSink previous = set_log_sink([&log](LogLevel level, std::string_view component,
                                             std::string_view message) {
        log.push_back(std::string(to_string(level)) + " " + std::string(component) + ": " +
                      std::string(message));
      });
      tester.world = std::make_unique<TestWorld>(skill_dir);
      if (!tester.world->load_error.empty()) {
        outcome.failure = tester.world->load_error;
      } else {
        const RunResult r = sandbox.call(ref);
        outcome.passed = r.ok;
        outcome.failure = r.error;
      }
      tester.world.reset();
      set_log_sink(std::move(previous));
      outcome.log = std::move(log);
      if (progress) {
        progress((outcome.passed ? "PASS " : "FAIL ") + relative + ": " + name);
        if (!outcome.passed) {
          progress("     " + outcome.failure);
          for (const auto& line : outcome.log) progress("     | " + line);
        }
      }
      report.tests.push_back(std::move(outcome));
    }
  }
  return report;
}

}  // namespace marvin::scripting
