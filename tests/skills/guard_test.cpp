// Guard mode's thread (core/skills/guard.h) on scripted eyes: an off request from another
// process ends the watch and is told; its stored state reads back; bad stored state is named.
#include <doctest/doctest.h>

#include <atomic>
#include <condition_variable>
#include <mutex>

#include "skills/guard.h"
#include "skills/scripted_eyes.h"

using marvin::skills::Guard;
using marvin::skills::GuardOptions;
using marvin::skills::GuardState;

TEST_CASE("guard: an off request ends the watch it names, and every change is told") {
  marvin::skills::ScriptedEyes eyes([](std::string) {});
  std::mutex mutex;
  std::condition_variable changed;
  std::vector<GuardState> told;
  std::atomic<std::int64_t> request{-1};
  GuardOptions o;
  o.look = std::chrono::milliseconds(5);
  o.changed = [&](const GuardState& s) {
    std::lock_guard lock(mutex);
    told.push_back(s);
    changed.notify_all();
  };
  o.off_requested = [&](const GuardState& s) { return request.load() == s.since_ms; };
  std::int64_t now = 1000;
  Guard guard(eyes, nullptr, [&] { return now; }, [](const std::string&, const std::string&) {},
              o);
  const GuardState on = guard.on();
  REQUIRE(on.on);
  request = on.since_ms;
  std::unique_lock lock(mutex);
  REQUIRE(changed.wait_for(lock, std::chrono::seconds(30), [&] { return told.size() == 2; }));
  CHECK(told[0].on);
  CHECK_FALSE(told[1].on);
  CHECK(told[1].by == marvin::skills::kOffByCommandLine);
  lock.unlock();
  CHECK_FALSE(guard.state().on);
}

TEST_CASE("guard: the stored state reads back; a broken one names its field") {
  GuardState s{true, 1234, 2, ""};
  const GuardState back =
      marvin::skills::guard_state_from_json(marvin::skills::guard_state_json(s));
  CHECK(back.on);
  CHECK(back.since_ms == 1234);
  CHECK(back.alerts == 2);
  CHECK_THROWS_WITH(marvin::skills::guard_state_from_json(R"({"on": "yes"})"),
                    "the guard state's 'on' is missing or of the wrong type");
  CHECK_THROWS_WITH(marvin::skills::guard_state_from_json("{"),
                    doctest::Contains("the guard state is not JSON"));
}

TEST_CASE("guard: ended with the program while on, it tells that nobody watches any more") {
  marvin::skills::ScriptedEyes eyes([](std::string) {});
  std::vector<GuardState> told;
  {
    GuardOptions o;
    o.look = std::chrono::milliseconds(5);
    o.changed = [&](const GuardState& s) { told.push_back(s); };  // this thread: on, the end
    Guard guard(eyes, nullptr, [] { return std::int64_t{7}; },
                [](const std::string&, const std::string&) {}, o);
    guard.on();
  }
  REQUIRE(told.size() == 2);
  CHECK_FALSE(told[1].on);
  CHECK(told[1].by == marvin::skills::kOffByShutdown);
}
