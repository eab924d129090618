// Lua skills against a fake robot: the `marvin` API, ask() through the coroutine, and the
// security corpus: each hostile request is stopped with a clear error while the host and
// a second, well-behaved skill keep working with their state intact.
#include <doctest/doctest.h>

#include <chrono>
#include <memory>
#include <string>
#include <vector>

#include "fake_robot.h"
#include "scripting/lua_skill.h"
#include "support/text.h"
#include "temp_skill.h"

namespace marvin::scripting {
namespace {

using test_support::contains;
using testing::FakeRobot;
using testing::TempDir;

Limits test_limits() {
  Limits limits;
  limits.memory_bytes = 2u << 20;
  limits.instructions = 300'000;
  limits.wall_time = std::chrono::hours(1);
  limits.string_bytes = 64u << 10;
  limits.pattern_steps = 100'000;
  limits.output_bytes = 2000;
  return limits;
}

struct Loaded {
  TempDir dir;
  FakeRobot robot;
  std::unique_ptr<LuaSkill> skill;

  Loaded(const std::string& id, const std::string& main_lua, std::vector<std::string> intents,
         std::vector<std::string> permissions = {}, Limits limits = test_limits(),
         Clock clock = {}) {
    dir.write("main.lua", main_lua);
    robot.skill_id = id;
    robot.permissions = {permissions.begin(), permissions.end()};
    robot.permissions.insert("speech");
    SkillSpec spec{id, dir.path(), "main.lua", std::move(intents), std::move(permissions)};
    skill = std::make_unique<LuaSkill>(spec, FakeRobot::api(), robot.host(), limits, std::move(clock));
  }

  marvin_status handle(const std::string& intent, const std::string& slots = "{}",
                       std::string* error = nullptr) {
    marvin_request request{sizeof(marvin_request), intent.c_str(), slots.c_str(), "utterance"};
    std::string ignored;
    return skill->handle(request, error != nullptr ? error : &ignored);
  }
};

// The well-behaved neighbour: counts in a global and in storage.
const char* kCounter = R"(
local count = 0
marvin.on("count", function()
  count = count + 1
  marvin.storage.set("count", count)
  marvin.say("count " .. count)
end)
)";

std::unique_ptr<Loaded> counter() {
  return std::make_unique<Loaded>("counter", kCounter, std::vector<std::string>{"count"},
                                  std::vector<std::string>{"storage"});
}

TEST_CASE("a handler gets its slots and speaks") {
  Loaded s("greeter", R"(
marvin.on("greet", function(slots, request)
  marvin.say("Hello " .. slots.name .. ", you said " .. request.utterance)
end)
)", {"greet"});
  CHECK(s.handle("greet", R"({"name":"Ada"})") == MARVIN_OK);
  REQUIRE(s.robot.said.size() == 1);
  CHECK(s.robot.said[0] == "Hello Ada, you said utterance");
}

TEST_CASE("marvin.home: devices as a table; set says true, or false and why") {
  Loaded s("lights", R"(
marvin.on("go", function()
  local home = marvin.home.devices()
  marvin.say(home.room .. ": " .. home.devices[1].name)
  marvin.say(tostring(marvin.home.set("lamp", {on = true, brightness = 40})))
  local ok, why = marvin.home.set("fan", "on")
  marvin.say(tostring(ok) .. ", " .. why)
end)
)", {"go"}, {"smarthome"});
  CHECK(s.handle("go", "{}") == MARVIN_OK);
  CHECK(s.robot.said == std::vector<std::string>{
                           "hall: lamp", "true",
                           "false, the fan did not report the new state within 3000 ms"});
  CHECK(s.robot.actions == std::vector<std::string>{R"(home.set lamp {"brightness":40,"on":true})",
                                                    "home.set fan on"});
  Loaded denied("nolights", R"(
marvin.on("go", function() marvin.home.set("lamp", "on") end)
)", {"go"});
  CHECK(denied.handle("go", "{}") != MARVIN_OK);
  CHECK(denied.robot.actions.empty());
}

TEST_CASE("marvin.phone: resolve, dial, the call's events, hang up; false and why") {
  Loaded s("caller", R"(
marvin.on("go", function()
  local who = marvin.phone.resolve("my daughter")
  marvin.say(who.say)
  marvin.say(tostring(marvin.phone.dial(who.number, who.name)))
  local e = marvin.phone.wait_event(1000)
  while e do
    marvin.say(e.event)
    e = marvin.phone.wait_event(1000)
  end
  marvin.say(tostring(marvin.phone.hang_up()))
  local ok, why = marvin.phone.hang_up()
  marvin.say(tostring(ok) .. ", " .. why)
  ok, why = marvin.phone.dial("0000")
  marvin.say(tostring(ok) .. ", " .. why)
end)
)", {"go"}, {"phone"});
  CHECK(s.handle("go", "{}") == MARVIN_OK);
  CHECK(s.robot.said == std::vector<std::string>{"Call my daughter?", "true", "ringing",
                                                 "answered", "true",
                                                 "false, there is no call to hang up",
                                                 "false, number: \"0000\" cannot be dialled"});
  CHECK(s.robot.actions == std::vector<std::string>{"phone.dial sip:anna@127.0.0.1 my daughter",
                                                    "phone.hang_up"});
  Loaded denied("nophone", R"(
marvin.on("go", function() marvin.phone.dial("0123") end)
)", {"go"});
  CHECK(denied.handle("go", "{}") != MARVIN_OK);
  CHECK(denied.robot.actions.empty());
}

TEST_CASE("loading reports the file and line, and intents without handlers") {
  TempDir dir;
  FakeRobot robot;
  dir.write("main.lua", "marvin.on('greet', function() end)\nlocal x = nil + 1\n");
  SkillSpec spec{"broken", dir.path(), "main.lua", {"greet"}, {}};
  CHECK_THROWS_WITH_AS(LuaSkill(spec, FakeRobot::api(), robot.host()),
                       "skill 'broken': main.lua:2: attempt to perform arithmetic on a nil value",
                       std::runtime_error);
  dir.write("main.lua", "marvin.on('greet', function() end)\n");
  spec.intents = {"greet", "farewell"};
  CHECK_THROWS_WITH_AS(LuaSkill(spec, FakeRobot::api(), robot.host()),
                       "skill 'broken': main.lua registers no handler for intent 'farewell' of "
                       "skill.json (add marvin.on(\"farewell\", function(slots) ... end))",
                       std::runtime_error);
  dir.write("main.lua", "marvin.on('greet', function() end)\nmarvin.on('typo', function() end)\n");
  spec.intents = {"greet"};
  CHECK_THROWS_WITH_AS(LuaSkill(spec, FakeRobot::api(), robot.host()),
                       "skill 'broken': main.lua:2: marvin.on: intent 'typo' is not declared in "
                       "skill.json (declared: greet)",
                       std::runtime_error);
  dir.write("main.lua", "marvin.on('greet', function() end)\nlocal x = ");
  CHECK_THROWS_WITH_AS(LuaSkill(spec, FakeRobot::api(), robot.host()),
                       "skill 'broken': main.lua:2: unexpected symbol near <eof>",
                       std::runtime_error);
}

TEST_CASE("ask suspends the handler until the answer, also inside pcall") {
  Loaded s("asker", R"(
marvin.on("order", function()
  local drink = marvin.ask("What would you like?")
  local ok, size = pcall(marvin.ask, "Which size?")
  marvin.say("One " .. size .. " " .. drink .. " coming up")
end)
)", {"order"});
  s.robot.answers = {"tea", "large"};
  CHECK(s.handle("order") == MARVIN_OK);
  CHECK(s.robot.asked == std::vector<std::string>{"What would you like?", "Which size?"});
  CHECK(s.robot.said.back() == "One large tea coming up");
}

TEST_CASE("ask from a coroutine the skill made is answered too") {
  Loaded s("asker", R"(
marvin.on("order", function()
  local co = coroutine.wrap(function() return marvin.ask("Name?") end)
  marvin.say("Hi " .. co())
end)
)", {"order"});
  s.robot.answers = {"Bob"};
  CHECK(s.handle("order") == MARVIN_OK);
  CHECK(s.robot.said.back() == "Hi Bob");
}

TEST_CASE("the user's thinking time does not count against the deadline") {
  std::int64_t fake_ms = 0;
  Limits limits = test_limits();
  limits.wall_time = std::chrono::milliseconds(100);
  Loaded s("asker", R"(
marvin.on("order", function()
  local a = marvin.ask("First?")
  local b = marvin.ask("Second?")
  marvin.say(a .. b)
end)
)", {"order"}, {}, limits, [&fake_ms] {
    return std::chrono::steady_clock::time_point(std::chrono::milliseconds(fake_ms));
  });
  s.robot.clock_ms = &fake_ms;
  s.robot.ask_thinking_ms = 60'000;  // a minute per answer
  s.robot.answers = {"x", "y"};
  std::string error;
  CHECK(s.handle("order", "{}", &error) == MARVIN_OK);
  CHECK(error.empty());
  CHECK(s.robot.said.back() == "xy");
}

TEST_CASE("an unanswered question ends the request as cancelled") {
  Loaded s("asker", "marvin.on('order', function() marvin.ask('Name?') marvin.say('never') end)",
           {"order"});
  std::string error;
  CHECK(s.handle("order", "{}", &error) == MARVIN_ERR_CANCELLED);
  CHECK(error == "skill 'asker': marvin.ask: the user did not answer");
  CHECK(s.robot.said == std::vector<std::string>{"Name?"});
}

TEST_CASE("storage, schedules, time and timers") {
  Loaded s("keeper", R"(
marvin.on("store", function(slots)
  marvin.storage.set("keys", slots.place)
  marvin.say("stored " .. marvin.storage.get("keys"))
  marvin.say(tostring(marvin.storage.get("missing")))
end)
marvin.on("remind", function()
  local r = marvin.schedule.add{title = "pills", at = "2026-01-05T20:00"}
  marvin.say("reminder " .. r.id .. " " .. r.title .. " at " .. r.at)
  marvin.say("now " .. marvin.now())
  marvin.after(30, function() marvin.say("thirty seconds later") end)
end)
)", {"store", "remind"}, {"storage", "schedule"});
  CHECK(s.handle("store", R"({"place":"on the hook"})") == MARVIN_OK);
  CHECK(s.robot.storage.at("keys") == "on the hook");
  CHECK(s.robot.said == std::vector<std::string>{"stored on the hook", "nil"});
  CHECK(s.handle("remind") == MARVIN_OK);
  CHECK(s.robot.reminders == std::vector<std::string>{R"({"at":"2026-01-05T20:00","title":"pills"})"});
  CHECK(s.robot.said.at(2) == "reminder 1 pills at 2026-01-05T20:00");
  CHECK(s.robot.said.at(3) == "now 1767603600");
  REQUIRE(s.skill->next_timer_ms().has_value());
  CHECK(*s.skill->next_timer_ms() == 1767603600000 + 30'000);
  std::string error;
  CHECK(s.skill->run_due_timers(1767603600000 + 29'999, &error) == MARVIN_OK);
  CHECK(s.robot.said.size() == 4);
  CHECK(s.skill->run_due_timers(1767603600000 + 30'000, &error) == MARVIN_OK);
  CHECK(s.robot.said.back() == "thirty seconds later");
  CHECK_FALSE(s.skill->next_timer_ms().has_value());
}

TEST_CASE("going places: go_to answers true or false and why; where_am_i names the room") {
  Loaded s("walker", R"(
marvin.on("go", function(slots)
  local ok, why = marvin.go_to(slots.place)
  if ok then marvin.say("in " .. marvin.where_am_i()) else marvin.say("no: " .. why) end
end)
)", {"go"}, {"motion", "sensors"});
  CHECK(s.handle("go", R"({"place":"kitchen"})") == MARVIN_OK);
  CHECK(s.handle("go", R"({"place":"garden"})") == MARVIN_OK);
  CHECK(s.robot.said == std::vector<std::string>{"in kitchen", "no: the garden door is blocked"});
  CHECK(s.robot.actions == std::vector<std::string>{"go_to kitchen", "go_to garden"});
  std::string error;
  Loaded denied("walker2", "marvin.on('go', function() marvin.go_to('kitchen') end)", {"go"});
  CHECK(denied.handle("go", "{}", &error) == MARVIN_ERR_PERMISSION);
  CHECK(contains(error, "marvin.go_to: permission 'motion' is not granted"));
  CHECK(denied.robot.actions.empty());
}

TEST_CASE("guiding: guide_to calls on_event with each event's table; false stops the trip") {
  Loaded s("guide", R"(
marvin.on("go", function(slots)
  local ok = marvin.guide_to(slots.place, 40, function(e)
    marvin.say(e.event .. " " .. e.distance_m .. (e.kind and (" " .. e.kind) or ""))
    return e.event ~= "obstacle" or slots.place ~= "garden"
  end)
  marvin.say(ok and "there" or "not there")
end)
marvin.on("bad", function() marvin.guide_to("kitchen", 40, function(e) error("boom") end) end)
)",
           {"go", "bad"}, {"motion"});
  CHECK(s.handle("go", R"({"place":"kitchen"})") == MARVIN_OK);
  CHECK(s.robot.said ==
        std::vector<std::string>{"step_down 0.43 step", "obstacle 1.0 low", "there"});
  s.robot.said.clear();
  std::string error;
  // on_event returned false at the obstacle: the trip ends as "stop" ends it.
  CHECK(s.handle("go", R"({"place":"garden"})", &error) == MARVIN_ERR_CANCELLED);
  CHECK(s.robot.said == std::vector<std::string>{"step_down 0.43 step", "obstacle 1.0 low"});
  CHECK(s.robot.room == "kitchen");
  // An error in on_event stops the trip and is the skill's error, in its line.
  CHECK(s.handle("bad", "{}", &error) != MARVIN_OK);
  CHECK(contains(error, "main.lua:9: boom"));
  CHECK(s.robot.actions == std::vector<std::string>{"guide_to kitchen speed=40",
                                                    "guide_to garden speed=40",
                                                    "guide_to kitchen speed=40"});
}

TEST_CASE("a call without permission fails in the skill's line and does nothing") {
  Loaded s("sneaky", R"(
marvin.on("drive", function()
  marvin.move("forward", 2)
end)
marvin.on("peek", function()
  local ok, err = pcall(marvin.storage.get, "other")
  marvin.say(err)
end)
)", {"drive", "peek"});
  std::string error;
  CHECK(s.handle("drive", "{}", &error) == MARVIN_ERR_PERMISSION);
  CHECK(error ==
        "skill 'sneaky': main.lua:3: marvin.move: permission 'motion' is not granted to skill "
        "'sneaky' (add \"motion\" to \"permissions\" in skill.json)");
  CHECK(s.robot.actions.empty());
  CHECK(s.robot.log.back() == error);
  CHECK(s.handle("peek") == MARVIN_OK);
  CHECK(contains(s.robot.said.back(), "permission 'storage' is not granted"));
}

// --- the corpus: hostile requests next to a healthy skill -----------------------------------

const char* kHostile = R"(
local visits = 0
marvin.on("ping", function() visits = visits + 1 marvin.say("pong " .. visits) end)
marvin.on("loop", function() while true do end end)
marvin.on("loop_pcall", function() while true do pcall(function() while true do end end) end end)
marvin.on("loop_coroutine", function()
  local co = coroutine.create(function() while true do end end)
  while true do coroutine.resume(co) end
end)
marvin.on("trip_then_talk", function()
  pcall(function() while true do end end)
  marvin.say("I escaped")
end)
marvin.on("recursion", function() local function f(n) return 1 + f(n + 1) end return f(1) end)
marvin.on("memory", function() local t = {} while true do t[#t + 1] = ("x"):rep(1000) .. #t end end)
marvin.on("memory_pcall", function()
  local t = {}
  for i = 1, 1e9 do pcall(function() for j = 1, 1e9 do t[#t + 1] = ("y"):rep(900) .. j end end) end
end)
marvin.on("gc_stop", function() collectgarbage("stop") end)
marvin.on("rep", function() return ("x"):rep(1e9) end)
marvin.on("pattern", function() return ("a"):rep(5000):find(("a*"):rep(12) .. "b") end)
marvin.on("gsub", function() return ("x"):rep(60000):gsub("x", "%0%0") end)
marvin.on("binary", function() return load(string.dump(function() end)) end)
marvin.on("binary_text", function() local f, err = load("\27LuaT\0") marvin.say(err) end)
marvin.on("string_mt", function() getmetatable("").__index.upper = function() return "pwned" end end)
marvin.on("string_mt_index", function() getmetatable("").__index = {} end)
marvin.on("replace_say", function() marvin.say = function() end end)
marvin.on("replace_marvin", function() marvin = {say = print} end)
marvin.on("rawset_marvin", function() rawset(_G, "marvin", {}) end)
marvin.on("replace_storage", function() marvin.storage.set = nil end)
marvin.on("os_execute", function() os.execute("rm -rf /") end)
marvin.on("io_open", function() io.open("/etc/passwd") end)
marvin.on("require_os", function() require "os" end)
marvin.on("debug_sethook", function() debug.sethook() end)
marvin.on("gc_finalizer", function() setmetatable({}, {__gc = function() while true do end end}) end)
marvin.on("tostring_loop", function() error(setmetatable({}, {__tostring = function() while true do end end})) end)
marvin.on("print_flood", function() while true do print(("z"):rep(100)) end end)
marvin.on("say_flood", function() for i = 1, 1000 do marvin.say("spam " .. i) end end)
marvin.on("log_flood", function() for i = 1, 1000 do marvin.log(("w"):rep(100)) end marvin.say("done") end)
marvin.on("no_permission", function() marvin.light("executing") end)
marvin.on("yield", function() coroutine.yield() end)
)";

const char* kIntents[] = {
    "ping", "loop", "loop_pcall", "loop_coroutine", "trip_then_talk", "recursion", "memory",
    "memory_pcall", "gc_stop", "rep", "pattern", "gsub", "binary", "binary_text", "string_mt",
    "string_mt_index", "replace_say", "replace_marvin", "rawset_marvin", "replace_storage",
    "os_execute", "io_open", "require_os", "debug_sethook", "gc_finalizer", "tostring_loop",
    "print_flood", "say_flood", "log_flood", "no_permission", "yield"};

struct Attack {
  const char* intent;
  const char* message;  // expected in the error ("" = the request succeeds)
  bool rebuild;         // a budget tripped: the state is rebuilt before the next request
};

const Attack kAttacks[] = {
    {"loop", "main.lua:4: instruction budget exceeded (300000 instructions in one request)", true},
    {"loop_pcall", "main.lua:5: instruction budget exceeded", true},
    {"loop_coroutine", "main.lua:8: instruction budget exceeded", true},
    {"trip_then_talk", "main.lua:11: instruction budget exceeded", true},
    {"recursion", "main.lua:14: ", true},
    {"memory", "main.lua:15: memory limit exceeded (the skill may use 2048 KB)", true},
    {"memory_pcall", "main.lua:18: memory limit exceeded (the skill may use 2048 KB)", true},
    {"gc_stop", "main.lua:20: collectgarbage(\"stop\") is not allowed in skills", false},
    {"rep", "main.lua:21: string.rep: the result would be over the limit of 65536 bytes", false},
    {"pattern", "main.lua:22: pattern too complex: gave up after", false},
    {"gsub", "main.lua:23: string.gsub: the result is over the limit of 65536 bytes", false},
    {"binary", "main.lua:24: attempt to call a nil value (field 'dump')", false},
    {"string_mt", "main.lua:26: attempt to modify read-only table 'string'", false},
    {"string_mt_index", "main.lua:27: attempt to modify read-only table 'string metatable'", false},
    {"replace_say", "main.lua:28: attempt to modify read-only table 'marvin'", false},
    {"replace_marvin", "main.lua:29: cannot replace 'marvin': it is part of the sandbox", false},
    {"rawset_marvin", "main.lua:30: cannot replace 'marvin'", false},
    {"replace_storage", "main.lua:31: attempt to modify read-only table 'marvin.storage'", false},
    {"os_execute", "main.lua:32: attempt to call a nil value (field 'execute')", false},
    {"io_open", "main.lua:33: attempt to index a nil value (global 'io')", false},
    {"require_os", "main.lua:34: no file 'os.lua' in the skill's folder", false},
    {"debug_sethook", "main.lua:35: attempt to index a nil value (global 'debug')", false},
    {"gc_finalizer", "main.lua:36: __gc metamethods are not allowed in skills", false},
    {"tostring_loop", "main.lua:37: error object is a table value", false},
    {"print_flood", "main.lua:38: instruction budget exceeded", true},
    {"say_flood", "main.lua:39: marvin.say: more than 20 sentences in one request", false},
    {"no_permission", "main.lua:41: marvin.light: permission 'light' is not granted to skill 'evil'", false},
    {"yield", "coroutine.yield() called outside a coroutine", false},
};

TEST_CASE("the hostile corpus: each attack is stopped, everyone else carries on") {
  auto good = counter();
  Loaded evil("evil", kHostile, {std::begin(kIntents), std::end(kIntents)});
  int expected_count = 0;
  int expected_rebuilds = 0;
  int pings = 0;
  for (const Attack& attack : kAttacks) {
    CAPTURE(std::string(attack.intent));
    evil.robot.said.clear();
    std::string error;
    const marvin_status status = evil.handle(attack.intent, "{}", &error);
    CHECK(status != MARVIN_OK);
    CHECK_MESSAGE(contains(error, std::string("skill 'evil': ") + attack.message), error);
    CHECK(evil.robot.log.back() == error);
    // Nothing the attack did after the trip reached the robot.
    for (const auto& sentence : evil.robot.said) CHECK(sentence.rfind("spam", 0) == 0);
    CHECK(evil.robot.actions.empty());
    if (attack.rebuild) ++expected_rebuilds;

    // The neighbour's state is intact and it keeps answering.
    good->robot.said.clear();
    CHECK(good->handle("count") == MARVIN_OK);
    ++expected_count;
    CHECK(good->robot.said == std::vector<std::string>{"count " + std::to_string(expected_count)});
    CHECK(good->robot.storage.at("count") == std::to_string(expected_count));

    // The attacker itself still works; its globals restart only after a rebuild.
    evil.robot.said.clear();
    CHECK(evil.handle("ping") == MARVIN_OK);
    pings = attack.rebuild ? 1 : pings + 1;
    CHECK(evil.robot.said == std::vector<std::string>{"pong " + std::to_string(pings)});
    CHECK(evil.skill->rebuilds() == expected_rebuilds);
  }
  CHECK(evil.skill->memory_bytes() < (2u << 20));
}

TEST_CASE("the corpus: a binary chunk given to load is refused as text") {
  Loaded evil("evil", kHostile, {std::begin(kIntents), std::end(kIntents)});
  CHECK(evil.handle("binary_text") == MARVIN_OK);
  CHECK(evil.robot.said.back() == "attempt to load a binary chunk (mode is 't')");
}

TEST_CASE("the corpus: print and log floods are capped in the skill's log") {
  Loaded evil("evil", kHostile, {std::begin(kIntents), std::end(kIntents)});
  REQUIRE(evil.handle("log_flood") == MARVIN_OK);
  CHECK(evil.robot.said.back() == "done");
  CHECK(evil.robot.log_bytes() < 2000 + 200);
  CHECK(contains(evil.robot.log.back(), "output limit reached (2000 bytes per request)"));
  evil.robot.log.clear();
  std::string error;
  CHECK(evil.handle("print_flood", "{}", &error) == MARVIN_ERR_INTERNAL);
  CHECK(evil.robot.log.size() <= 2000 / 100 + 2);  // capped lines, the notice, the error
}

TEST_CASE("the corpus: string tampering leaves strings working") {
  Loaded evil("evil", kHostile, {std::begin(kIntents), std::end(kIntents)});
  CHECK(evil.handle("string_mt") != MARVIN_OK);
  Loaded probe("probe", "marvin.on('upper', function() marvin.say(('abc'):upper()) end)",
               {"upper"});
  CHECK(probe.handle("upper") == MARVIN_OK);
  CHECK(probe.robot.said.back() == "ABC");
}

TEST_CASE("\"stop\" interrupts a busy handler as cancelled") {
  Loaded s("busy", "marvin.on('work', function() while true do end end)", {"work"},
           {}, [] {
             Limits limits = test_limits();
             limits.instructions = 1'000'000'000;
             return limits;
           }());
  s.robot.cancelled = true;
  std::string error;
  CHECK(s.handle("work", "{}", &error) == MARVIN_ERR_CANCELLED);
  CHECK(error == "skill 'busy': main.lua:1: cancelled (the user said stop)");
}

}  // namespace
}  // namespace marvin::scripting
