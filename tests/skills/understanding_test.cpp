// The built-in skills' manifests (and the Lua examples) as `marvin run` registers them:
// requests as people type them reach the right skill with the right slots.
#include <doctest/doctest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "interpret/eval_labels.h"
#include "interpret/interpreter.h"
#include "skills/manifest.h"
#include "skills/registry.h"

namespace {

namespace fs = std::filesystem;
using marvin::interpret::Builtin;
using marvin::interpret::builtin_eval_label;
using marvin::interpret::default_eval_label;
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
  for (const char* skill : {"hello", "schedule", "time"})
    add_skill(in, repo / "skills-builtin" / skill);
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

  auto plants = in.match(
      "hey marvin, could you please remind me to water the plants at "
      "half past two tomorrow",
      context());
  REQUIRE(plants);
  CHECK(plants->slots.at("task").text == "water the plants");
  CHECK(plants->slots.at("when").value.at("at") == "2026-11-26T14:30");
}

TEST_CASE("a part of the day belongs to the time, not to the task") {
  const Interpreter in = robot_interpreter();  // Wednesday 08:06 in Berlin
  auto plumber = in.match("remind me to call the plumber tomorrow morning at 6", context());
  REQUIRE(plumber);
  CHECK(plumber->slots.at("task").text == "call the plumber");
  CHECK(plumber->slots.at("when").value.at("at") == "2026-11-26T06:00");
  auto door = in.match("remind me to lock the door this evening", context());
  REQUIRE(door);
  CHECK(door->slots.at("task").text == "lock the door");
  CHECK(door->slots.at("when").value.at("at") == "2026-11-25T19:00");
  // A time alone is never the task ("at 6" was): the skill asks for the task instead.
  auto bare = in.match("remind me at 6", context());
  REQUIRE(bare);
  CHECK(bare->slots.count("task") == 0);
  CHECK(bare->slots.at("when").value.at("at") == "2026-11-25T18:00");
  auto alarm = in.match("wake me up at 6 tomorrow", context());
  REQUIRE(alarm);
  CHECK(alarm->intent == "remind");
  CHECK(alarm->slots.count("task") == 0);
  CHECK(alarm->slots.at("when").value.at("at") == "2026-11-26T06:00");
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

TEST_CASE("thanks and goodbyes are answered; the words asked about in a language are not") {
  const Interpreter in = robot_interpreter();
  CHECK(reading(in, "thank you marvin") == "hello/thanks");
  CHECK(reading(in, "Thanks a lot!") == "hello/thanks");
  CHECK(reading(in, "thank you so much for your help") == "hello/thanks");
  CHECK(reading(in, "goodbye") == "hello/goodbye");
  CHECK(reading(in, "see you later marvin") == "hello/goodbye");
  CHECK(reading(in, "good night robot") == "hello/goodbye");
  // Written for this test, not among the interpreter's out-of-scope sentences.
  for (const char* mention :
       {"how would i say thank you in swahili", "what is the polish word for goodbye"}) {
    CAPTURE(mention);
    CHECK(reading(in, mention).rfind("hello/", 0) != 0);
  }
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

namespace {

// Every built-in skill, as `marvin run` loads them.
Interpreter builtin_interpreter() {
  Interpreter in;
  for (const auto& entry : fs::directory_iterator(fs::path(MARVIN_REPO_DIR) / "skills-builtin")) {
    if (fs::exists(entry.path() / "skill.json")) add_skill(in, entry.path());
  }
  return in;
}

}  // namespace

// When Marvin cannot tell two intents apart it asks "Did you want <description> or
// <description>?"; without a description it would have to say "Finding people and things
// (anyone in)".
TEST_CASE("every shipped intent has a description to ask with") {
  const fs::path repo = MARVIN_REPO_DIR;
  int intents = 0;
  for (const fs::path& folder : {repo / "skills-builtin", repo / "skills-examples" / "lua"}) {
    for (const auto& entry : fs::directory_iterator(folder)) {
      if (!fs::exists(entry.path() / "skill.json")) continue;
      const marvin::skills::Manifest m = marvin::skills::load_manifest(entry.path() / "skill.json");
      for (const auto& intent : m.intents) {
        CAPTURE(m.id + "/" + intent.name);
        CHECK_FALSE(intent.description.empty());
        ++intents;
      }
    }
  }
  CHECK(intents > 60);
}

TEST_CASE("where did I leave it: the thing, not the words before it, is what to look for") {
  const Interpreter in = builtin_interpreter();
  for (const auto& [text, thing] : std::vector<std::pair<std::string, std::string>>{
           {"where did I leave my glasses", "my glasses"},
           {"where have I put my keys?", "my keys"},
           {"where did my purse go", "my purse"},
           {"where has the remote gone", "the remote"}}) {
    CAPTURE(text);
    const auto m = in.match(text, context());
    REQUIRE(m);
    CHECK(m->skill_id + "/" + m->intent == "finding/where_is");
    CHECK(m->slots.at("what").text == thing);
  }
}

// A guard against fitting the development set: requests written for this test alone
// (tests/interpret/heldout_requests.tsv, never in a manifest) keep the goals' rates with every
// built-in skill loaded, as `marvin run` loads them. A question naming the right intent counts
// as right; for an out-of-scope request, acting on anything is wrong.
TEST_CASE("held-out requests: the right intent and out of scope declined at the goals' rates") {
  const Interpreter in = builtin_interpreter();
  const fs::path repo = MARVIN_REPO_DIR;
  std::ifstream file(repo / "tests" / "interpret" / "heldout_requests.tsv");
  REQUIRE(file);
  int in_scope = 0, right = 0, out_of_scope = 0, acted = 0;
  std::string line;
  while (std::getline(file, line)) {
    if (line.empty() || line[0] == '#') continue;
    const auto tab = line.rfind('\t');
    REQUIRE(tab != std::string::npos);
    const std::string text = line.substr(0, tab), gold = line.substr(tab + 1);
    std::vector<std::string> chosen;
    if (const char* b = builtin_eval_label(in.builtin(text))) {
      chosen.emplace_back(b);
    } else {
      const Understanding u = in.understand(text, context());
      if (u.outcome == Understanding::Outcome::kMatch) {
        chosen.push_back(default_eval_label(u.match->skill_id, u.match->intent));
      } else if (u.outcome == Understanding::Outcome::kAsk) {
        for (const auto& c : u.choices) chosen.push_back(default_eval_label(c.skill_id, c.intent));
        chosen.emplace_back("(asked)");
      }
    }
    const bool picked = std::find(chosen.begin(), chosen.end(), gold) != chosen.end();
    if (gold == "none") {
      ++out_of_scope;
      const bool wrong = !chosen.empty() && chosen.back() != "(asked)";
      if (wrong) MESSAGE("acted on: " << text << " -> " << chosen.front());
      acted += wrong ? 1 : 0;
    } else {
      ++in_scope;
      if (!picked) MESSAGE("missed: " << text << " (" << gold << ")");
      right += picked ? 1 : 0;
    }
  }
  REQUIRE(in_scope >= 30);
  REQUIRE(out_of_scope >= 30);
  CHECK(right * 100 >= in_scope * 85);     // >= 85 % to the right intent (or asked about it)
  CHECK(acted * 100 <= out_of_scope * 3);  // <= 3 % of out-of-scope requests acted on
}

TEST_CASE("asking how a device is set, and asking not to forget something") {
  const Interpreter in = builtin_interpreter();
  for (const char* text :
       {"could you tell me the temperature of the fridge", "check whether i left the heater on",
        "how warm is the thermostat set", "is the garage door locked"}) {
    CAPTURE(std::string(text));
    CHECK(reading(in, text) == "home/query");
  }
  // A thing in the world is no device, though the template fits word for word.
  CHECK(reading(in, "what's the temperature of the sun").rfind("home/", 0) != 0);

  auto bins = in.match("don't let me forget to put the bins out on friday", context());
  REQUIRE(bins);
  CHECK(bins->intent == "remind");
  CHECK(bins->slots.at("task").text == "put the bins out");
  CHECK(bins->slots.at("when").value.at("at") == "2026-11-27T09:00");
  auto mum = in.match("make sure i remember to call mum at 6pm", context());
  REQUIRE(mum);
  CHECK(mum->intent == "remind");
  CHECK(mum->slots.at("task").text == "call mum");
  CHECK(mum->slots.at("when").value.at("at") == "2026-11-25T18:00");
}

TEST_CASE("the time somewhere else: the time intent with the place as a slot") {
  const Interpreter in = builtin_interpreter();
  auto london = in.match("Hey, what is the time in London?", context());
  REQUIRE(london);
  CHECK(london->skill_id == "time");
  CHECK(london->intent == "time");
  CHECK(london->slots.at("place").text == "london");
  auto here = in.match("what time is it", context());
  REQUIRE(here);
  CHECK(here->intent == "time");
  CHECK(here->slots.count("place") == 0);
  // The time skill's declared synonym: people read the time off "the clock".
  CHECK(reading(in, "what does the clock say") == "time/time");
}

TEST_CASE("the sun is not the clock: sunset and sunrise are declined, the time is not") {
  const Interpreter in = builtin_interpreter();
  // Written for this test, not among the interpreter's out-of-scope sentences.
  for (const char* sky : {"when is sunset", "what time is sunset tomorrow", "what time is sunrise"}) {
    CAPTURE(sky);
    CHECK(reading(in, sky).rfind("time/", 0) != 0);
  }
  CHECK(reading(in, "what time is it now") == "time/time");
}

TEST_CASE("going somewhere: the user's wish to go is guiding, Marvin's own trip is navigation") {
  Interpreter in;
  const fs::path repo = MARVIN_REPO_DIR;
  for (const char* skill : {"hello", "navigation", "guidance", "finding", "time"})
    add_skill(in, repo / "skills-builtin" / skill);
  CHECK(reading(in, "i want to go to the kitchen") == "guidance/guide");
  CHECK(reading(in, "I'd like to go to the bathroom") == "guidance/guide");
  CHECK(reading(in, "help me get to the bedroom") == "guidance/guide");
  CHECK(reading(in, "take me to the kitchen") == "guidance/guide");
  CHECK(reading(in, "go to the kitchen") == "navigation/go_to");
  CHECK(reading(in, "is there anything in my way") == "guidance/way_clear");
}

TEST_CASE("everyday phrasings with every built-in skill loaded") {
  Interpreter in;
  const fs::path repo = MARVIN_REPO_DIR;
  for (const char* skill : {"hello", "faces", "finding", "guidance", "home", "navigation",
                            "phone", "schedule", "time"}) {
    add_skill(in, repo / "skills-builtin" / skill);
  }
  // The doorbell: the front door, not whoever stands in front of the robot.
  CHECK(reading(in, "who is at the door") == "finding/anyone_in");
  CHECK(reading(in, "is someone at the front door") == "finding/anyone_in");
  CHECK(reading(in, "who is this") == "faces/who");
  CHECK(reading(in, "delete Peter from my contacts") == "schedule/remove_contact");
  CHECK(reading(in, "remove my son from the phone book") == "schedule/remove_contact");
  CHECK(reading(in, "add a contact Mary Jones 555 1234") == "schedule/add_contact");
  CHECK(reading(in, "what day is good friday") == "time/day");
  CHECK(reading(in, "is there anything in my way") == "guidance/way_clear");
  CHECK(reading(in, "any obstacles ahead") == "guidance/way_clear");
}
