// Guard mode's thread (core/skills/guard.h) on scripted eyes: an off request from another
// process ends the watch and is told; its stored state reads back; bad stored state is named.
#include "skills/guard.h"

#include <doctest/doctest.h>

#include <atomic>
#include <cmath>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <optional>

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
  Guard guard(
      eyes, nullptr, [&] { return now; }, [](const std::string&, const std::string&) {}, o);
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
    Guard guard(
        eyes, nullptr, [] { return std::int64_t{7}; },
        [](const std::string&, const std::string&) {}, o);
    guard.on();
  }
  REQUIRE(told.size() == 2);
  CHECK_FALSE(told[1].on);
  CHECK(told[1].by == marvin::skills::kOffByShutdown);
}

namespace {

// A map with one screen (a TV) straight ahead, 2 to 3 m away, 10 degrees each side.
struct TvAhead final : marvin::navigation::GoingPlaces {
  marvin::navigation::GoResult go_to(std::string_view, const marvin::navigation::WaitFn&) override {
    return {};
  }
  void stop() override {}
  std::optional<std::string> where_am_i() override { return "living room"; }
  std::optional<std::string> screen_at(double bearing_deg, double distance_m) override {
    if (std::abs(bearing_deg) <= 10 && distance_m >= 2 && distance_m <= 3) return "tv";
    return std::nullopt;
  }
};

// A face 48 px high (0.18 m at about 2.1 m): centred at column `centre_x` of 640.
std::string face_at(double centre_x) {
  return R"({"name": "", "box": [)" + std::to_string(centre_x - 20) + R"(, 200, 40, 48]})";
}

struct Watch {
  std::mutex mutex;
  std::condition_variable changed;
  GuardState last;
  int alerts = 0;
  GuardOptions options() {
    GuardOptions o;
    o.look = std::chrono::milliseconds(2);
    o.changed = [this](const GuardState& s) {
      std::lock_guard lock(mutex);
      last = s;
      changed.notify_all();
    };
    return o;
  }
  void alert() {
    std::lock_guard lock(mutex);
    ++alerts;
    changed.notify_all();
  }
  template <typename Until>
  bool wait(Until until) {
    std::unique_lock lock(mutex);
    return changed.wait_for(lock, std::chrono::seconds(60), until);
  }
};

}  // namespace

// Issue 22: "pictures of people on a TV are the false alarms to avoid". A stranger's face on
// the TV the map knows, over a long watch (100 looks), never alerts; the same stranger beside
// the TV does; a face inside a box the detector calls a "tv" is a picture without any map.
TEST_CASE("guard: a face on the TV is a picture across a long watch; one beside it alerts") {
  TvAhead map;
  marvin::skills::ScriptedEyes eyes([](std::string) {});
  Watch watch;
  auto guard = [&] {
    return std::make_unique<Guard>(
        eyes, &map, [] { return std::int64_t{1}; },
        [&](const std::string&, const std::string&) { watch.alert(); }, watch.options());
  };
  SUBCASE("on the TV: 100 looks, no alert") {
    eyes.set_view(R"({"width": 640, "faces": [)" + face_at(320) + "]}");
    auto g = guard();
    g->on();
    REQUIRE(watch.wait([&] { return watch.last.pictures >= 100; }));
    CHECK(watch.alerts == 0);
    CHECK(g->state().alerts == 0);
  }
  SUBCASE("beside the TV (17 degrees off), the same face alerts") {
    eyes.set_view(R"({"width": 640, "faces": [)" + face_at(320 - 320 * 0.577 * 0.9) + "]}");
    auto g = guard();
    g->on();
    REQUIRE(watch.wait([&] { return watch.alerts == 1; }));
    CHECK(g->state().pictures == 0);
  }
  SUBCASE("both: the TV's face is set aside, the visitor beside it still alerts") {
    eyes.set_view(R"({"width": 640, "faces": [)" + face_at(320) + "," + face_at(100) + "]}");
    auto g = guard();
    g->on();
    REQUIRE(watch.wait([&] { return watch.alerts == 1; }));
  }
  SUBCASE("no map: a face inside a box the detector labels tv is a picture") {
    eyes.set_view(R"({"width": 640, "faces": [)" + face_at(200) +
                  R"(], "objects": [{"label": "television", "class": "tv",
                        "box": [120, 150, 200, 150], "score": 0.6}]})");
    auto g = std::make_unique<Guard>(
        eyes, nullptr, [] { return std::int64_t{1}; },
        [&](const std::string&, const std::string&) { watch.alert(); }, watch.options());
    g->on();
    REQUIRE(watch.wait([&] { return watch.last.pictures >= 40; }));
    CHECK(watch.alerts == 0);
  }
}

TEST_CASE("guard: is_picture needs the face inside the tv's box or at the map's screen") {
  const nlohmann::json tv_look = nlohmann::json::parse(
      R"({"width": 640, "objects": [{"class": "tv", "box": [100, 150, 100, 150]}]})");
  CHECK(marvin::skills::is_picture(nlohmann::json::parse(face_at(150)), tv_look, nullptr));
  CHECK_FALSE(marvin::skills::is_picture(nlohmann::json::parse(face_at(400)), tv_look, nullptr));
  TvAhead map;
  const nlohmann::json plain = nlohmann::json::parse(R"({"width": 640})");
  CHECK(marvin::skills::is_picture(nlohmann::json::parse(face_at(320)), plain, &map));
  // Straight ahead but 48 px is about 2.1 m: a face twice as big is 1 m away, in front of the TV.
  CHECK_FALSE(marvin::skills::is_picture(
      nlohmann::json::parse(R"({"name": "", "box": [280, 200, 80, 96]})"), plain, &map));
}

TEST_CASE("guard: state stored before pictures were counted still reads") {
  const GuardState s = marvin::skills::guard_state_from_json(
      R"({"on": false, "since_unix_ms": 5, "alerts": 1, "by": "Anna"})");
  CHECK(s.pictures == 0);
  CHECK(s.by == "Anna");
  CHECK_THROWS_WITH(
      marvin::skills::guard_state_from_json(
          R"({"on": false, "since_unix_ms": 5, "alerts": 1, "by": "", "pictures": "x"})"),
      "the guard state's 'pictures' is missing or of the wrong type");
}
