// The built-in skills' manifests (and the Lua examples) as `marvin run` registers them:
// requests as people type them reach the right skill with the right slots.
#include <doctest/doctest.h>

#include <filesystem>
#include <string>

#include "interpret/interpreter.h"
#include "skills/manifest.h"
#include "skills/registry.h"

namespace {

namespace fs = std::filesystem;
using marvin::interpret::Builtin;
using marvin::interpret::Context;
using marvin::interpret::Interpreter;
using marvin::interpret::Understanding;

void add_skill(Interpreter& in, const fs::path& dir) {
  marvin::skills::Manifest m = marvin::skills::load_manifest(dir / "skill.json");
  for (const auto& intent : m.intents) in.add(marvin::skills::intent_spec(m, intent));
}

Interpreter robot_interpreter() {
  Interpreter in;
  const fs::path repo = MARVIN_REPO_DIR;
  for (const char* skill : {"hello", "schedule", "time"}) add_skill(in, repo / "skills-builtin" / skill);
  for (const char* skill : {"hello", "medication", "where-is"}) {
    add_skill(in, repo / "skills-examples" / "lua" / skill);
  }
  return in;
}

Context context() {
  Context c;
  c.now_utc_ms = 1795600000000;  // Wednesday 2026-11-25, 08:06 in Berlin
  c.time_zone = "Europe/Berlin";
  return c;
}

std::string reading(const Interpreter& in, const std::string& text) {
  Understanding u = in.understand(text, context());
  if (u.outcome != Understanding::Outcome::kMatch) return "(" + u.reason + ")";
  return u.match->skill_id + "/" + u.match->intent;
}

}  // namespace

TEST_CASE("the issue's phrasings reach the right skill with the right slots") {
  const Interpreter in = robot_interpreter();
  CHECK(reading(in, "what's the time") == "time/time");
  CHECK(reading(in, "Hey, what is the time?") == "time/time");
  CHECK(reading(in, "Could you tell me what time it is?") == "time/time");
  CHECK(reading(in, "can you tell me the date today") == "time/day");
  CHECK(reading(in, "What do I have scheduled for next week?") == "schedule/agenda");

  auto alarm = in.match("Set my alarm for 6am", context());
  REQUIRE(alarm);
  CHECK(alarm->skill_id == "schedule");
  CHECK(alarm->intent == "remind");
  CHECK(alarm->slots.at("when").value.at("at") == "2026-11-26T06:00");  // next 6am

  auto half_six = in.match("set alarm at 6:30 a.m", context());
  REQUIRE(half_six);
  CHECK(half_six->intent == "remind");
  CHECK(half_six->slots.at("when").value.at("at") == "2026-11-26T06:30");

  auto meeting = in.match("remind me about the meeting", context());
  REQUIRE(meeting);
  CHECK(meeting->skill_id == "schedule");  // not the medication skill
  CHECK(meeting->slots.at("task").text == "the meeting");

  auto plants = in.match("hey marvin, could you please remind me to water the plants at "
                         "half past two tomorrow", context());
  REQUIRE(plants);
  CHECK(plants->slots.at("task").text == "water the plants");
  CHECK(plants->slots.at("when").value.at("at") == "2026-11-26T14:30");
}

TEST_CASE("timers: set, how long is left, cancel") {
  const Interpreter in = robot_interpreter();
  auto timer = in.match("set a timer for 10 minutes", context());
  REQUIRE(timer);
  CHECK(timer->intent == "set_timer");
  CHECK(timer->slots.at("duration").value == 600);
  CHECK(reading(in, "how long is left") == "schedule/timer_left");
  CHECK(reading(in, "cancel the timer") == "schedule/cancel_timer");
  CHECK(in.builtin("cancel the timer") == Builtin::kNone);  // a request, not "stop"
}

TEST_CASE("stop still wins, with or without politeness") {
  const Interpreter in = robot_interpreter();
  for (const char* text : {"stop", "Marvin, stop!", "please stop it now", "cancel that",
                           "hey could you stop that please", "never mind"}) {
    CAPTURE(std::string(text));
    CHECK(in.builtin(text) == Builtin::kStop);
  }
  CHECK(in.builtin("cancel my dentist reminder") == Builtin::kNone);
  CHECK(in.builtin("stop reminding me about the bins") == Builtin::kNone);
}

TEST_CASE("a Lua skill with only templates gains from tolerant matching") {
  const Interpreter in = robot_interpreter();
  // where-is declares "where (is|are) my {item}" and nothing else for this.
  CHECK_FALSE(in.match_exact("do you know where my keys are", context()));
  auto keys = in.match("do you know where my keys are", context());
  REQUIRE(keys);
  CHECK(keys->skill_id == "where-is");
  CHECK(keys->intent == "recall");
  auto glasses = in.match("Marvin, where are my glasses please?", context());
  REQUIRE(glasses);
  CHECK(glasses->slots.at("item").text == "glasses");
}
