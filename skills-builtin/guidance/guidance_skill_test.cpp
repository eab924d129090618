// The guidance skill through the SkillHarness: sonar sweeps told apart (wall vs low thing by
// D_x = D cos θ, D_y = D_x tan θ), the camera's things with their side, guiding and "I can't".
#include <doctest/doctest.h>

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
        Lines{"Follow me to the kitchen. I'll stop if something is in the way.",
              "We're there: the kitchen."});
  CHECK(h.robot().room() == "kitchen");
  CHECK(h.say("guide me to the garage") == Lines{"I don't know where the garage is."});
  h.robot().block_place("bedroom", "the bedroom door is blocked");
  h.robot().add_place("bedroom", "bedroom");
  CHECK(h.say("guide me to the bedroom").back() ==
        "I can't guide you to the bedroom: the bedroom door is blocked.");
  CHECK(h.robot().room() == "kitchen");
}
