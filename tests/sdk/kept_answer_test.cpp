// Retrying an acting call after MARVIN_ERR_TRUNCATED does not act twice: the host keeps the
// answer that did not fit for the skill's next, identical call (marvin/abi.h).
#include <doctest/doctest.h>

#include <algorithm>
#include <marvin/skill.hpp>
#include <marvin/testing/mock_robot.hpp>
#include <string>

namespace {

// Many things in view, so that look_around's answer is longer than any first buffer.
std::string crowded_view() {
  nlohmann::json objects = nlohmann::json::array();
  for (int i = 0; i < 12; ++i) {
    objects.push_back({{"label", "cup"}, {"box", {40 * i, 300, 30, 30}}});
  }
  return nlohmann::json{{"faces", nlohmann::json::array()}, {"objects", objects}}.dump();
}

std::size_t turns(const marvin::testing::MockRobot& robot) {
  const auto& actions = robot.actions();
  return static_cast<std::size_t>(
      std::count_if(actions.begin(), actions.end(),
                    [](const std::string& a) { return a.rfind("turn", 0) == 0; }));
}

struct LookingRobot {
  LookingRobot() : robot("finder", {"camera", "motion", "sensors"}) {
    robot.add_place("hall", "hall");
    robot.set_room("hall");
    robot.set_room_view("hall", crowded_view());
  }
  marvin_status look(std::string* buffer, std::size_t* length) {
    marvin_text_out out{buffer->data(), buffer->size(), 0};
    const marvin_status status = robot.api()->look_around(robot.host(), 4, &out);
    *length = out.length;
    return status;
  }
  marvin::testing::MockRobot robot;
};

TEST_CASE("look_around into a tiny buffer turns once; the retry gets the whole answer") {
  LookingRobot r;
  std::string tiny(8, '\0');
  std::size_t length = 0;
  REQUIRE(r.look(&tiny, &length) == MARVIN_ERR_TRUNCATED);
  const std::size_t one_circle = turns(r.robot);
  REQUIRE(one_circle > 0);
  REQUIRE(length > 8);

  std::string buffer(length + 1, '\0');
  REQUIRE(r.look(&buffer, &length) == MARVIN_OK);
  CHECK(turns(r.robot) == one_circle);  // no second circle
  buffer.resize(length);
  const auto seen = nlohmann::json::parse(buffer);
  CHECK(seen["stops"] == 4);
  CHECK_FALSE(seen["seen"].empty());

  // The kept answer was given once: the same call again is a new look.
  std::string roomy(1 << 20, '\0');
  REQUIRE(r.look(&roomy, &length) == MARVIN_OK);
  CHECK(turns(r.robot) == 2 * one_circle);
}

TEST_CASE("a retry still too small keeps the answer; another call in between drops it") {
  LookingRobot r;
  std::string tiny(8, '\0');
  std::size_t length = 0;
  REQUIRE(r.look(&tiny, &length) == MARVIN_ERR_TRUNCATED);
  const std::size_t one_circle = turns(r.robot);
  std::string small(16, '\0');
  REQUIRE(r.look(&small, &length) == MARVIN_ERR_TRUNCATED);  // still too small: kept again
  CHECK(turns(r.robot) == one_circle);
  CHECK(std::string(r.robot.api()->last_error(r.robot.host())) ==
        "the answer did not fit the buffer");

  std::int64_t now = 0;
  REQUIRE(r.robot.api()->now(r.robot.host(), &now) == MARVIN_OK);  // another call
  std::string buffer(length + 1, '\0');
  REQUIRE(r.look(&buffer, &length) == MARVIN_OK);
  CHECK(turns(r.robot) == 2 * one_circle);  // so this one looked again

  // A call with other arguments is not the retry either.
  REQUIRE(r.look(&tiny, &length) == MARVIN_ERR_TRUNCATED);
  marvin_text_out out{buffer.data(), buffer.size(), 0};
  REQUIRE(r.robot.api()->look_around(r.robot.host(), 6, &out) == MARVIN_OK);
  CHECK(turns(r.robot) > 3 * one_circle);
}

TEST_CASE("ask into a tiny buffer asks once; the retry gets the user's answer") {
  marvin::testing::MockRobot robot("asker");
  robot.add_answer("the blue one with the white stripes, please");
  robot.add_answer("no");
  std::string tiny(4, '\0');
  marvin_text_out out{tiny.data(), tiny.size(), 0};
  REQUIRE(robot.api()->ask(robot.host(), "Which one?", &out) == MARVIN_ERR_TRUNCATED);
  std::string buffer(out.length + 1, '\0');
  out = marvin_text_out{buffer.data(), buffer.size(), 0};
  REQUIRE(robot.api()->ask(robot.host(), "Which one?", &out) == MARVIN_OK);
  buffer.resize(out.length);
  CHECK(buffer == "the blue one with the white stripes, please");
  CHECK(robot.asked() == std::vector<std::string>{"Which one?"});
  CHECK(robot.answers_left() == 1);  // "no" is still for the next question
}

TEST_CASE("the C++ layer's look_around: one circle however long the answer") {
  LookingRobot r;
  std::string roomy(1 << 20, '\0');
  std::size_t length = 0;
  REQUIRE(r.look(&roomy, &length) == MARVIN_OK);  // fits at once: one circle for sure
  REQUIRE(length > 512);                          // longer than the C++ layer's first buffer
  const std::size_t one_circle = turns(r.robot);
  REQUIRE(one_circle > 0);
  r.robot.clear();
  marvin::Robot robot(r.robot.api(), r.robot.host());
  const nlohmann::json seen = robot.look_around(4);
  CHECK(seen.dump().size() == length);
  CHECK(turns(r.robot) == one_circle);
}

}  // namespace
