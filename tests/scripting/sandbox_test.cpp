// The sandbox on its own: what a script can reach, the budgets, the guarded string
// functions. Every hostile script must fail with a clear message and leave the state
// usable (or tripped, when a budget ran out).
#include <doctest/doctest.h>

#include <chrono>
#include <string>
#include <vector>

#include "scripting/sandbox.h"
#include "support/text.h"
#include "temp_skill.h"

namespace marvin::scripting {
namespace {

using test_support::contains;
using testing::TempDir;

Limits small_limits() {
  Limits limits;
  limits.memory_bytes = 2u << 20;
  limits.instructions = 300'000;
  limits.wall_time = std::chrono::hours(1);  // the fake clocks below decide deadlines
  limits.pattern_steps = 200'000;
  limits.string_bytes = 64u << 10;
  limits.output_bytes = 1000;
  return limits;
}

struct Fixture {
  TempDir dir;
  std::vector<std::string> output;
  Sandbox sandbox{"probe", dir.path(), small_limits()};
  Fixture() {
    sandbox.set_output([this](LogLevel, std::string_view text) { output.emplace_back(text); });
  }
  RunResult run(const std::string& code) { return sandbox.run(code, "main.lua"); }
  // Evaluates an expression and returns tostring() of it (via print).
  std::string eval(const std::string& expression) {
    output.clear();
    const RunResult r = run("print(" + expression + ")");
    REQUIRE_MESSAGE(r.ok, r.error);
    REQUIRE(output.size() == 1);
    return output.front();
  }
};

TEST_CASE("only the allowlisted globals exist") {
  Fixture f;
  for (const char* name : {"io", "debug", "package", "dofile", "loadfile", "warn"}) {
    CHECK_MESSAGE(f.eval(name) == "nil", name);
  }
  CHECK(f.eval("string.dump") == "nil");
  CHECK(f.eval("os.execute") == "nil");
  CHECK(f.eval("os.getenv") == "nil");
  CHECK(f.eval("os.exit") == "nil");
  CHECK(f.eval("os.remove") == "nil");
  CHECK(f.eval("type(os.time())") == "number");
  CHECK(f.eval("os.date('%Y', 0)") == "1970");
  CHECK(f.eval("math.floor(2.5)") == "2");
  CHECK(f.eval("utf8.char(72, 105)") == "Hi");
  CHECK(f.eval("table.concat({1, 2, 3}, ',')") == "1,2,3");
  CHECK(f.eval("('abc'):upper()") == "ABC");
  CHECK(f.eval("select('#', coroutine.running())") == "2");
}

TEST_CASE("errors name the skill's file and line") {
  Fixture f;
  const RunResult r = f.run("local x = 1\nlocal y = nil\nreturn x + y\n");
  CHECK_FALSE(r.ok);
  CHECK_FALSE(r.tripped);
  CHECK(r.error == "main.lua:3: attempt to perform arithmetic on a nil value (local 'y')");
}

TEST_CASE("os.execute, io.open, require 'os' and debug.sethook are unreachable") {
  Fixture f;
  RunResult r = f.run("os.execute('touch /tmp/pwned')");
  CHECK(r.error == "main.lua:1: attempt to call a nil value (field 'execute')");
  r = f.run("io.open('/etc/passwd')");
  CHECK(r.error == "main.lua:1: attempt to index a nil value (global 'io')");
  r = f.run("local os2 = require 'os'");
  CHECK(r.error == "main.lua:1: no file 'os.lua' in the skill's folder");
  r = f.run("debug.sethook()");
  CHECK(r.error == "main.lua:1: attempt to index a nil value (global 'debug')");
  r = f.run("require '../../etc/passwd'");
  CHECK(contains(r.error, "main.lua:1: require(\"../../etc/passwd\"): module names are letters"));
  CHECK(f.eval("1 + 1") == "2");  // the state goes on
}

TEST_CASE("require loads the skill's own modules as text, once") {
  Fixture f;
  f.dir.write("lib/greeting.lua", "count = (count or 0) + 1\nreturn {hello = function() return 'hi' end}\n");
  f.dir.write("binary.lua", std::string("\x1bLuaT\x00", 6));
  CHECK(f.eval("require('lib.greeting').hello()") == "hi");
  CHECK(f.eval("require('lib.greeting') == require('lib.greeting')") == "true");
  CHECK(f.eval("count") == "1");
  const RunResult r = f.run("require 'binary'");
  CHECK(contains(r.error, "attempt to load a binary chunk (mode is 't')"));
}

TEST_CASE("require refuses a symlink that leads out of the skill's folder") {
  Fixture f;
  TempDir outside;
  outside.write("secret.lua", "return 'secret'");
  std::filesystem::create_symlink(outside.path() / "secret.lua", f.dir.path() / "secret.lua");
  const RunResult r = f.run("return require 'secret'");
  CHECK(r.error == "main.lua:1: 'secret.lua' is outside the skill's folder");
}

TEST_CASE("binary chunks cannot be loaded, text chunks get the skill's environment") {
  Fixture f;
  RunResult r = f.run("load(string.dump(print))");
  CHECK(r.error == "main.lua:1: attempt to call a nil value (field 'dump')");
  CHECK(f.eval("select(2, load('\\27LuaT\\0'))") ==
        "attempt to load a binary chunk (mode is 't')");
  r = f.run("load(function() return nil end)");
  CHECK(r.error ==
        "main.lua:1: load: skills may only load text chunks given as strings (got a function)");
  CHECK(f.eval("(function() answer = 42; return load('return answer')() end)()") == "42");
  CHECK(f.eval("load('return io')()") == "nil");
}

TEST_CASE("the string metatable and the library tables are read-only") {
  Fixture f;
  RunResult r = f.run("getmetatable('').__index.upper = function() return 'pwned' end");
  CHECK(r.error == "main.lua:1: attempt to modify read-only table 'string'");
  r = f.run("getmetatable('').__index = {}");
  CHECK(r.error == "main.lua:1: attempt to modify read-only table 'string metatable'");
  r = f.run("string.rep = nil");
  CHECK(r.error == "main.lua:1: attempt to modify read-only table 'string'");
  r = f.run("rawset(table, 'insert', print)");
  CHECK(r.error == "main.lua:1: attempt to modify read-only table");
  r = f.run("setmetatable(math, nil)");
  CHECK(r.error == "main.lua:1: attempt to modify read-only table");
  r = f.run("string = {}");
  CHECK(r.error ==
        "main.lua:1: cannot replace 'string': it is part of the sandbox (use a local variable or "
        "another name)");
  r = f.run("rawset(_G, 'print', error)");
  CHECK(contains(r.error, "cannot replace 'print'"));
  r = f.run("setmetatable(_G, nil)");
  CHECK(r.error == "main.lua:1: cannot change a protected metatable");
  CHECK(f.eval("('abc'):upper()") == "ABC");
  CHECK(f.eval("string.upper('x')") == "X");
  // pairs() over a library lists its functions without handing out the real table.
  CHECK(f.eval("(function() local n = 0 for k in pairs(math) do n = n + 1 end return n > 20 end)()") ==
        "true");
  CHECK(f.eval("#string > -1") == "true");
  // A skill's own globals are its own business.
  CHECK(f.eval("(function() greeting = 'hello'; return greeting end)()") == "hello");
}

TEST_CASE("__gc metamethods are refused") {
  Fixture f;
  const RunResult r = f.run("setmetatable({}, {__gc = function() while true do end end})");
  CHECK(r.error ==
        "main.lua:1: __gc metamethods are not allowed in skills (Lua runs them outside the "
        "skill's time and instruction budget)");
  CHECK(f.eval("getmetatable(setmetatable({}, {__index = {a = 1}})).__index.a") == "1");
}

TEST_CASE("an endless loop trips the instruction budget, even inside pcall and coroutines") {
  const char* scripts[] = {
      "while true do end",
      "while true do pcall(function() while true do end end) end",
      "local ok = pcall(function() while true do end end)\nprint('survived')",
      "xpcall(function() while true do end end, function(e) print('handler') return e end)\n"
      "print('survived')",
      "local co = coroutine.wrap(function() while true do end end)\nco()\nprint('survived')",
      "while true do coroutine.resume(coroutine.create(function() while true do end end)) end",
      "while true do pcall(coroutine.wrap(function() while true do end end)) end",
      "xpcall(function() while true do end end, function(e) while true do end end)",
      "do local x <close> = setmetatable({}, {__close = function() print('closing') end})\n"
      "while true do end end",
  };
  for (const std::string script : scripts) {
    CAPTURE(script);
    Fixture f;
    const RunResult r = f.run(script);
    CHECK_FALSE(r.ok);
    CHECK(r.tripped);
    CHECK(contains(r.error, "instruction budget exceeded (300000 instructions in one request)"));
    CHECK(r.error.rfind("main.lua:", 0) == 0);
    CHECK_MESSAGE(f.output.empty(), f.output.front());  // nothing ran after the trip
    CHECK(f.sandbox.instructions_used() <= 300'000 + 2 * kHookInterval);
  }
}

TEST_CASE("a fresh invocation has a fresh budget") {
  Fixture f;
  CHECK(f.run("while true do end").tripped);
  const RunResult r = f.run("local n = 0 for i = 1, 1000 do n = n + i end print(n)");
  CHECK(r.ok);
  CHECK(f.output.back() == "500500");
}

TEST_CASE("the wall-clock deadline stops a loop (fake clock)") {
  TempDir dir;
  auto now = std::chrono::steady_clock::time_point{};
  Limits limits = small_limits();
  limits.instructions = 1'000'000'000;  // the clock must trip first
  limits.wall_time = std::chrono::milliseconds(50);
  Sandbox sandbox("probe", dir.path(), limits, [&now] {
    now += std::chrono::milliseconds(1);  // every look at the clock costs a millisecond
    return now;
  });
  const RunResult r = sandbox.run("while true do pcall(function() while true do end end) end",
                                  "main.lua");
  CHECK(r.tripped);
  CHECK(contains(r.error, "time limit exceeded (50 ms for one request)"));
  CHECK(sandbox.instructions_used() < 200 * static_cast<std::uint64_t>(kHookInterval));
}

TEST_CASE("the clock paused for the user does not count") {
  TempDir dir;
  auto now = std::chrono::steady_clock::time_point{};
  Limits limits = small_limits();
  limits.wall_time = std::chrono::milliseconds(100);
  Sandbox sandbox("probe", dir.path(), limits, [&now] { return now; });
  sandbox.begin_invocation();
  sandbox.pause_clock();
  now += std::chrono::minutes(5);  // the user thinks
  sandbox.resume_clock();
  now += std::chrono::milliseconds(99);
  CHECK_FALSE(sandbox.over_budget(1));
  now += std::chrono::milliseconds(2);
  CHECK(sandbox.over_budget(1));
  CHECK(contains(sandbox.trip_reason(), "time limit exceeded (100 ms"));
}

TEST_CASE("memory bombs trip the memory cap, pcall cannot swallow it") {
  const char* scripts[] = {
      "local t = {} while true do t[#t + 1] = ('x'):rep(1000) .. #t end",
      "local t = {} while true do pcall(function() while true do t[#t + 1] = ('y'):rep(1000) .. #t end end) end",
      "local s = 'x' while true do s = s .. s end",
      "local t = {} for i = 1, 1e9 do t[i] = {i, i, i, i} end",
  };
  for (const std::string script : scripts) {
    CAPTURE(script);
    Fixture f;
    const RunResult r = f.run(script);
    CHECK(r.tripped);
    const bool memory = contains(r.error, "memory limit exceeded (the skill may use 2048 KB)");
    const bool string_cap = contains(r.error, "over the limit");
    CHECK((memory || string_cap));
    CHECK(f.sandbox.memory_used() <= (2u << 20) + (256u << 10));
  }
}

TEST_CASE("string.rep and gsub refuse huge results") {
  Fixture f;
  RunResult r = f.run("local s = string.rep('x', 1e8)");
  CHECK(r.error == "main.lua:1: string.rep: the result would be over the limit of 65536 bytes");
  r = f.run("local s = ('ab'):rep(1e7, ',')");
  CHECK(contains(r.error, "string.rep: the result would be over the limit"));
  r = f.run("local s = ('x'):rep(60000):gsub('x', 'yy')");
  CHECK(r.error == "main.lua:1: string.gsub: the result is over the limit of 65536 bytes");
  CHECK_FALSE(r.tripped);
  CHECK(f.eval("('x'):rep(3, '-')") == "x-x-x");
}

TEST_CASE("catastrophic patterns give up with a clear error") {
  Fixture f;
  RunResult r = f.run("string.find(('a'):rep(5000), ('a*'):rep(12) .. 'b')");
  CHECK_FALSE(r.ok);
  CHECK(contains(r.error, "pattern too complex: gave up after"));
  r = f.run("for w in ('a'):rep(3000):gmatch(('a-'):rep(10) .. 'b') do end");
  CHECK(contains(r.error, "pattern too complex"));
  // A loop of patterns is charged to the instruction budget.
  r = f.run("while true do pcall(string.find, ('a'):rep(300), ('a*'):rep(3) .. 'b') end");
  CHECK(r.tripped);
  CHECK(contains(r.error, "instruction budget exceeded"));
}

TEST_CASE("the pattern functions behave like Lua's") {
  Fixture f;
  CHECK(f.eval("(string.find('hello world', 'o w'))") == "5");
  CHECK(f.eval("select(2, string.find('hello world', 'o w'))") == "7");
  CHECK(f.eval("(string.find('a+b', '+', 1, true))") == "2");
  CHECK(f.eval("(string.match('key = value', '(%w+)%s*=%s*(%w+)'))") == "key");
  CHECK(f.eval("select(2, string.match('key = value', '(%w+)%s*=%s*(%w+)'))") == "value");
  CHECK(f.eval("string.match('  trim  ', '^%s*(.-)%s*$')") == "trim");
  CHECK(f.eval("(string.match('hello', '()ll()'))") == "3");
  CHECK(f.eval("(string.gsub('hello world', 'o', '0'))") == "hell0 w0rld");
  CHECK(f.eval("(string.gsub('hello world', '(%w+)', '<%1>'))") == "<hello> <world>");
  CHECK(f.eval("(string.gsub('abc', '%w', {a = 1, b = false}))") == "1bc");
  CHECK(f.eval("(string.gsub('abc', '%w', function(c) return c:upper() end))") == "ABC");
  CHECK(f.eval("select(2, string.gsub('abc', '', '-'))") == "4");
  CHECK(f.eval("(string.gsub('THE (quick) fox', '%f[%a]%a+', 'x'))") == "x (x) x");
  CHECK(f.eval("(string.gsub('f(a(b)c)', '%b()', ''))") == "f");
  CHECK(f.eval("(function() local t = {} for k, v in string.gmatch('a=1, b=2', '(%w+)=(%w+)') do t[#t + 1] = k .. v end return table.concat(t, ' ') end)()") ==
        "a1 b2");
  CHECK(f.eval("(string.match('2026-01-05', '(%d+)-(%d+)-(%d+)'))") == "2026");
  CHECK(f.eval("(string.find('abc', 'b', -2))") == "2");
  const RunResult r = f.run("string.find('x', '[a')");
  CHECK(r.error == "main.lua:1: malformed pattern (missing ']')");
}

TEST_CASE("collectgarbage('stop') is refused; counting works") {
  Fixture f;
  const RunResult r = f.run("collectgarbage('stop')");
  CHECK(r.error ==
        "main.lua:1: collectgarbage(\"stop\") is not allowed in skills (allowed: \"collect\", "
        "\"count\", \"step\", \"isrunning\")");
  CHECK(f.eval("collectgarbage('count') > 0") == "true");
  CHECK(f.eval("collectgarbage('isrunning')") == "true");
}

TEST_CASE("error objects are never turned into text by running script code") {
  Fixture f;
  const RunResult r = f.run(
      "error(setmetatable({}, {__tostring = function() while true do end end}))");
  CHECK_FALSE(r.ok);
  CHECK_FALSE(r.tripped);
  CHECK(r.error ==
        "main.lua:1: error object is a table value (raise errors with a string: error(\"what "
        "went wrong\"))");
  CHECK(f.run("error('plain', 0)").error == "main.lua:1: plain");
}

TEST_CASE("print floods are capped per invocation") {
  Fixture f;
  const RunResult r = f.run("for i = 1, 10000 do print(('x'):rep(50)) end");
  CHECK(r.ok);
  std::size_t bytes = 0;
  for (const auto& line : f.output) bytes += line.size();
  CHECK(f.output.size() == 20 + 1);  // 20 lines of 50 bytes fit in 1000, then one notice
  CHECK(contains(f.output.back(), "output limit reached (1000 bytes per request)"));
  CHECK(bytes < 1200);
  const RunResult endless = f.run("while true do print('flood') end");
  CHECK(endless.tripped);
}

}  // namespace
}  // namespace marvin::scripting
