// A Lua skill's look_around against the host's own table (the MockRobot): the Lua API's
// first buffer is small, its retry after MARVIN_ERR_TRUNCATED gets the answer the host kept,
// so the robot turns one circle, not two (marvin/abi.h, marvin_text_out).
#include <doctest/doctest.h>

#include <algorithm>
#include <marvin/testing/mock_robot.hpp>
#include <nlohmann/json.hpp>

#include "scripting/lua_skill.h"
#include "temp_skill.h"

namespace marvin::scripting {
namespace {

std::size_t lua_turns(const marvin::testing::MockRobot& robot) {
  const auto& actions = robot.actions();
  return static_cast<std::size_t>(
      std::count_if(actions.begin(), actions.end(),
                    [](const std::string& a) { return a.rfind("turn", 0) == 0; }));
}

TEST_CASE("a Lua skill's look_around turns one circle however long the answer") {
  marvin::testing::MockRobot robot("looker", {"camera", "motion", "sensors"});
  robot.add_place("hall", "hall");
  robot.set_room("hall");
  nlohmann::json objects = nlohmann::json::array();
  for (int i = 0; i < 12; ++i)
    objects.push_back({{"label", "cup"}, {"box", {40 * i, 300, 30, 30}}});
  robot.set_room_view(
      "hall", nlohmann::json{{"faces", nlohmann::json::array()}, {"objects", objects}}.dump());

  // One look into a buffer it fits at once: how many turns one circle is, and how long.
  std::string roomy(1 << 20, '\0');
  marvin_text_out out{roomy.data(), roomy.size(), 0};
  REQUIRE(robot.api()->look_around(robot.host(), 4, &out) == MARVIN_OK);
  REQUIRE(out.length > 256);  // longer than the Lua API's first buffer
  const std::size_t one_circle = lua_turns(robot);
  REQUIRE(one_circle > 0);
  robot.clear();

  testing::TempDir dir;
  dir.write("main.lua", R"(
marvin.on("look", function()
  local found = marvin.finding.look_around(4)
  marvin.say("seen " .. #found.seen)
end)
)");
  LuaSkill skill({"looker", dir.path(), "main.lua", {"look"}, {"camera", "motion", "sensors"}},
                 robot.api(), robot.host());
  marvin_request request{sizeof(marvin_request), "look", "{}", "look around"};
  std::string error;
  REQUIRE_MESSAGE(skill.handle(request, &error) == MARVIN_OK, error);
  CHECK(lua_turns(robot) == one_circle);
  REQUIRE(robot.said().size() == 1);
  CHECK(robot.said()[0] != "seen 0");
}

}  // namespace
}  // namespace marvin::scripting
