// The guidance skill through the SkillHarness: sonar sweeps told apart (wall vs low thing by
// D_x = D cos θ, D_y = D sin θ; a step down from the downward readings), the camera's things
// with their side, guiding slowly with what happens on the way told, and "I can't".
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <marvin/testing/skill_harness.hpp>

using Lines = std::vector<std::string>;

namespace {

// A sweep 0..60 degrees by 15 against a vertical surface `x` ahead and `height` above the
// sonar (no echo above it).
std::vector<marvin_scan_point> sweep(double x, double height, std::int64_t now) {
  std::vector<marvin_scan_point> out;
  for (int a = 0; a <= 60; a += 15) {
    const double t = a * 3.14159265358979 / 180;
    const bool hit = x * std::tan(t) <= height;
    out.push_back({static_cast<double>(a), hit ? x / std::cos(t) : 2.5, now});
  }
  return out;
}

}  // namespace

TEST_CASE("is the way clear: a wall, a low thing, nothing") {
  marvin::testing::SkillHarness h(GUIDANCE_SKILL_DIR);
  const std::int64_t now = 1767603600000;
  h.robot().set_scan(sweep(1.0, 3.0, now));
  CHECK(h.say("is the way clear") == Lines{"No: a wall or something tall, one metre ahead."});
  h.robot().set_scan(sweep(0.8, 0.1, now));  // a box 10 cm higher than the sonar
  CHECK(h.say("is the way clear") == Lines{"No: something low, 80 centimetres ahead."});
  h.robot().set_scan(sweep(9, 0, now));
  CHECK(h.say("is the way clear") == Lines{"Yes, the way ahead is clear for at least 2.5 metres."});
  // Asked the other way round, the answer turns round too.
  CHECK(h.say("is there anything in my way") ==
        Lines{"No, nothing is in the way for at least 2.5 metres."});
  h.robot().set_scan(sweep(1.0, 3.0, now));
  CHECK(h.say("is anything in my way") == Lines{"Yes: a wall or something tall, one metre ahead."});
}

TEST_CASE("what's in front of me: the sonar's obstacle and what the camera recognises") {
  marvin::testing::SkillHarness h(GUIDANCE_SKILL_DIR);
  h.robot().set_scan(sweep(1.5, 3.0, 1767603600000));
  h.robot().set_camera_view(
      R"({"width":640,"height":480,"faces":[{"name":"Anna","box":[500,100,60,60]}],)"
      R"("objects":[{"label":"chair","box":[40,200,120,160]}]})");
  CHECK(h.say("what's in front of me") ==
        Lines{"A wall or something tall, 1.5 metres ahead; a chair, on your left and Anna, on "
              "your right."});
  h.robot().set_camera_failure("camera /dev/video0: unplugged");
  CHECK(h.say("what is ahead") == Lines{"A wall or something tall, 1.5 metres ahead."});
}

TEST_CASE("guide me: there, an unknown place, a blocked way") {
  marvin::testing::SkillHarness h(GUIDANCE_SKILL_DIR);
  h.robot().add_place("kitchen", "kitchen");
  CHECK(h.say("guide me to the kitchen") ==
        Lines{"Follow me to the kitchen. I'll go slowly and tell you what's ahead.",
              "We're there: the kitchen."});
  CHECK(h.robot().room() == "kitchen");
  const Lines actions = h.robot().actions();
  CHECK(std::find(actions.begin(), actions.end(), "guide_to kitchen speed=50") != actions.end());
  CHECK(h.say("guide me to the garage") == Lines{"I don't know where the garage is."});
  // "my ...": the map's place when it has one by the plain name, else said as "your ...".
  CHECK(h.say("take me to my chair") == Lines{"I don't know where your chair is."});
  h.robot().set_room("hall");
  CHECK(h.say("take me to my kitchen").back() == "We're there: the kitchen.");
  h.robot().block_place("bedroom", "the bedroom door is blocked");
  h.robot().add_place("bedroom", "bedroom");
  CHECK(h.say("guide me to the bedroom").back() ==
        "I can't guide you to the bedroom: the bedroom door is blocked.");
  CHECK(h.robot().room() == "kitchen");
}

namespace {

// Downward readings (-45, -30, -15) over a floor 0.25 m below the sonar; `drop_from_m`:
// the floor is 0.2 m lower from there on (horizontal distance).
std::vector<marvin_scan_point> floor_sweep(double drop_from_m, std::int64_t now) {
  std::vector<marvin_scan_point> out;
  for (int a = -45; a < 0; a += 15) {
    const double t = -a * 3.14159265358979 / 180;
    const double x = 0.25 / std::tan(t);
    const double h = x < drop_from_m ? 0.25 : 0.45;
    out.push_back({static_cast<double>(a), h / std::sin(t), now});
  }
  return out;
}

}  // namespace

TEST_CASE("is the way clear: a step down is told from the floor, nearer than a wall") {
  marvin::testing::SkillHarness h(GUIDANCE_SKILL_DIR);
  const std::int64_t now = 1767603600000;
  std::vector<marvin_scan_point> scan = floor_sweep(0.6, now);  // -15 deg sees the drop
  for (const auto& p : sweep(2.0, 3.0, now)) scan.push_back(p);
  h.robot().set_scan(scan);
  CHECK(h.say("is the way clear") == Lines{"No: a step down, 90 centimetres ahead."});
  CHECK(h.say("what's in front of me") == Lines{"A step down, 90 centimetres ahead."});
  CHECK(h.intent_of("is there something in front of me") == "guidance/in_front");
  scan = floor_sweep(9, now);  // the floor everywhere: a clear way, not "something low"
  for (const auto& p : sweep(9, 0, now)) scan.push_back(p);
  h.robot().set_scan(scan);
  CHECK(h.say("is the way clear") == Lines{"Yes, the way ahead is clear for at least 2.5 metres."});
}

TEST_CASE("guiding tells the way: distance, a turn, an obstacle the camera names, a step down") {
  marvin::testing::SkillHarness h(GUIDANCE_SKILL_DIR);
  h.robot().add_place("kitchen", "kitchen");
  h.robot().set_camera_view(
      R"({"width":640,"height":480,"faces":[],"objects":[{"label":"chair","box":[40,200,120,160]},)"
      R"({"label":"cup","box":[300,200,20,20]}]})");
  h.robot().add_guide_event(R"({"event":"start","distance_left_m":6.2})");
  h.robot().add_guide_event(R"({"event":"turn","turn":"left","distance_m":0.95})");
  h.robot().add_guide_event(
      R"({"event":"obstacle","distance_m":1.0,"kind":"low","stopped":false})");
  h.robot().add_guide_event(R"({"event":"step_down","distance_m":0.43,"kind":"step"})");
  CHECK(h.say("guide me to the kitchen") ==
        Lines{"Follow me to the kitchen. I'll go slowly and tell you what's ahead.",
              "It's about 6 metres.", "In one metre, we turn left.",
              "Chair, one metre ahead, on your left.",
              "Careful: step down ahead, 40 centimetres. I've stopped.",
              "We're there: the kitchen."});
  // Without a camera the sonar's words; stopping for it is said.
  h.robot().set_camera_failure("camera /dev/video0: unplugged");
  h.robot().add_guide_event(
      R"({"event":"obstacle","distance_m":0.4,"kind":"wall","stopped":true})");
  CHECK(h.say("guide me to the kitchen")[1] ==
        "A wall or something tall, 40 centimetres ahead. I'm stopping.");
}

TEST_CASE("guiding: \"stop\" during the trip stops the wheels and says nothing more") {
  marvin::testing::SkillHarness h(GUIDANCE_SKILL_DIR);
  h.robot().add_place("kitchen", "kitchen");
  h.robot().add_guide_event(R"({"event":"start","distance_left_m":3,"then_stop":true})");
  h.robot().add_guide_event(R"({"event":"turn","turn":"left","distance_m":1})");
  const Lines said = h.say("guide me to the kitchen");
  CHECK(std::find(said.begin(), said.end(), "We're there: the kitchen.") == said.end());
  CHECK(std::find(said.begin(), said.end(), "In one metre, we turn left.") == said.end());
  const Lines actions = h.robot().actions();
  CHECK(std::find(actions.begin(), actions.end(), "stop") != actions.end());
  CHECK(h.robot().room() == "hall");
}
