// The faces skill through the SkillHarness, with the MockRobot's scripted camera.
#include <doctest/doctest.h>

#include <algorithm>
#include <marvin/testing/skill_harness.hpp>

using Lines = std::vector<std::string>;

namespace {

const char* kStranger = R"({"faces":[{"name":"","box":[200,120,140,140]}]})";

}  // namespace

TEST_CASE("who is this: a stranger, then Anna after 'this is Anna' and a yes") {
  marvin::testing::SkillHarness h(FACES_SKILL_DIR);
  h.robot().set_camera_view(kStranger);
  CHECK(h.say("who is this") == Lines{"That's someone I don't know."});
  CHECK(h.say("this is anna", {"yes"}) ==
        Lines{"Shall I remember this face as Anna?", "Nice to meet you, Anna. I'll remember your face."});
  CHECK(h.robot().enrolled_faces() == Lines{"Anna"});
  const Lines& actions = h.robot().actions();
  CHECK(std::count(actions.begin(), actions.end(), "enroll_face Anna frames=5") == 1);
  CHECK(h.say("who is in front of you") == Lines{"That's Anna."});
  CHECK(h.say("forget anna's face") == Lines{"OK, I forgot Anna's face."});
  CHECK(h.robot().enrolled_faces().empty());
  CHECK(h.say("who is at the door") == Lines{"That's someone I don't know."});
  CHECK(h.say("forget anna's face") == Lines{"I don't know Anna's face."});
}

TEST_CASE("no enrolment without a yes, with no face or with several") {
  marvin::testing::SkillHarness h(FACES_SKILL_DIR);
  h.robot().set_camera_view(kStranger);
  CHECK(h.say("remember this face as bob", {"no"}) ==
        Lines{"Shall I remember this face as Bob?", "OK, I won't remember it."});
  h.robot().set_camera_view(R"({"faces":[]})");
  CHECK(h.say("this is bob", {"yes"}).back() == "I don't see a face. Please look at me and try again.");
  h.robot().set_camera_view(
      R"({"faces":[{"name":"","box":[0,0,10,10]},{"name":"Anna","box":[50,0,10,10]}]})");
  CHECK(h.say("this is bob", {"yes"}).back() ==
        "I see more than one face. Please let Bob stand alone in front of me.");
  CHECK(h.say("who do you see") == Lines{"I see Anna and someone I don't know."});
  CHECK(h.robot().enrolled_faces().empty());
}

TEST_CASE("what do you see; a camera that fails is said plainly") {
  marvin::testing::SkillHarness h(FACES_SKILL_DIR);
  h.robot().set_camera_view(
      R"({"faces":[{"name":"","box":[0,0,10,10]},{"name":"","box":[50,0,10,10]}],
          "objects":[{"label":"cup","box":[1,2,3,4],"score":0.9}]})");
  CHECK(h.say("what do you see") == Lines{"I see two people I don't know and a cup."});
  h.robot().set_camera_failure("camera /dev/video0: reading a frame failed (device unplugged?)");
  CHECK(h.say("who is this") ==
        Lines{"Sorry, I can't see anything right now: my camera is not working."});
  CHECK(h.say("this is anna", {"yes"}).back() ==
        "Sorry, I can't see anything right now: my camera is not working.");
  CHECK(h.robot().enrolled_faces().empty());
}

TEST_CASE("these are my keys; do you see my keys") {
  marvin::testing::SkillHarness h(FACES_SKILL_DIR);
  h.robot().set_camera_view(R"({"faces":[]})");
  CHECK(h.say("do you see my keys") ==
        Lines{"I don't know what your keys look like. Show them to me and say \"these are my keys\"."});
  CHECK(h.say("these are my keys") == Lines{"OK, I'll remember what your keys look like."});
  CHECK(h.say("do you see my keys") == Lines{"No, I don't see your keys."});
  h.robot().set_camera_view(R"({"faces":[],"objects":[{"label":"keys","box":[5,5,40,20]}]})");
  CHECK(h.say("can you see my keys") == Lines{"Yes, I see your keys."});
  const Lines& actions = h.robot().actions();
  CHECK(std::count(actions.begin(), actions.end(), "teach_object keys") == 1);
}
