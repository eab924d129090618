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

TEST_CASE("this is my daughter: the contact book's name, a relation with a name, or asked") {
  marvin::testing::SkillHarness h(FACES_SKILL_DIR);
  h.robot().add_contact_json(R"({"name": "Anna Schmidt", "relation": "daughter"})");
  h.robot().set_camera_view(kStranger);
  CHECK(h.say("this is my daughter", {"yes"}) ==
        Lines{"Shall I remember this face as Anna Schmidt?",
              "Nice to meet you, Anna Schmidt. I'll remember your face."});
  CHECK(h.say("this is my neighbour peter", {"yes"}) ==
        Lines{"Shall I remember this face as Peter?", "Nice to meet you, Peter. I'll remember your face."});
  // A relation no contact has: its name is asked.
  CHECK(h.say("this is my son", {"It's Tom.", "yes"}) ==
        Lines{"What is your son's name?", "Shall I remember this face as Tom?",
              "Nice to meet you, Tom. I'll remember your face."});
  CHECK(h.robot().enrolled_faces() == Lines{"Anna Schmidt", "Peter", "Tom"});
}

TEST_CASE("forget my face: the one known face in view after a yes; a relation's face by name") {
  marvin::testing::SkillHarness h(FACES_SKILL_DIR);
  h.robot().add_contact_json(R"({"name": "Anna Schmidt", "relation": "daughter"})");
  h.robot().set_camera_view(R"({"faces":[]})");
  CHECK(h.say("forget my face") ==
        Lines{"I don't see anyone. Please look at me, or tell me whose face to forget."});
  h.robot().set_camera_view(kStranger);
  CHECK(h.say("forget my face") == Lines{"I don't know your face, so there is nothing to forget."});
  h.say("remember my face", {"Tom", "yes"});
  h.say("this is my daughter", {"yes"});
  REQUIRE(h.robot().enrolled_faces() == Lines{"Tom", "Anna Schmidt"});
  h.robot().set_camera_view(R"({"faces":[{"name":"Tom","box":[200,120,140,140]}]})");
  CHECK(h.say("delete my face", {"no"}) == Lines{"Shall I forget your face, Tom?", "OK, I'll keep it."});
  CHECK(h.robot().enrolled_faces() == Lines{"Tom", "Anna Schmidt"});
  CHECK(h.say("forget my face", {"yes"}) ==
        Lines{"Shall I forget your face, Tom?", "OK, I forgot Tom's face."});
  CHECK(h.say("forget my daughter's face") == Lines{"OK, I forgot Anna Schmidt's face."});
  CHECK(h.robot().enrolled_faces().empty());
}

TEST_CASE("remember my face: asks the name (said any way), then who am I is answered to me") {
  marvin::testing::SkillHarness h(FACES_SKILL_DIR);
  h.robot().set_camera_view(kStranger);
  CHECK(h.say("what's my name") ==
        Lines{"I don't know your face yet. To introduce yourself, say \"remember my face\"."});
  CHECK(h.say("remember my face", {"My name is Tom.", "yes"}) ==
        Lines{"What name should I remember the face by?", "Shall I remember this face as Tom?",
              "Nice to meet you, Tom. I'll remember your face."});
  CHECK(h.robot().enrolled_faces() == Lines{"Tom"});
  CHECK(h.say("who am I") == Lines{"You're Tom."});
  CHECK(h.say("do you know my name") == Lines{"You're Tom."});
  CHECK(h.say("do you recognise me") == Lines{"You're Tom."});
  CHECK(h.say("who is this") == Lines{"That's Tom."});
  // Nobody in view: asked about themselves, the speaker is told where to stand.
  h.robot().set_camera_view(R"({"faces":[]})");
  CHECK(h.say("who am I") == Lines{"I can't see you. Please come and stand in front of me."});
  CHECK(h.say("who is this") == Lines{"I don't see anyone."});
}

TEST_CASE("who is Anna: answered from the contact book, not the camera") {
  marvin::testing::SkillHarness h(FACES_SKILL_DIR);
  h.robot().add_contact_json(
      R"({"name": "Anna Schmidt", "aliases": ["Annie"], "relation": "daughter"})");
  h.robot().add_contact_json(R"({"name": "Tom"})");
  // A name that is no contact is a question about who is here.
  h.robot().set_camera_view(kStranger);
  CHECK(h.say("who is Bob") == Lines{"That's someone I don't know."});
  // Contacts are answered without the camera (it fails from here on).
  h.robot().set_camera_failure("camera /dev/video0: reading a frame failed");
  CHECK(h.say("who is Anna") == Lines{"Anna Schmidt is your daughter."});
  CHECK(h.say("who's annie again") == Lines{"Annie is Anna Schmidt, your daughter."});
  CHECK(h.say("tell me who Tom is") == Lines{"Tom is one of your contacts."});
  // The relation names the contact: "my daughter".
  CHECK(h.say("who is my daughter") == Lines{"Your daughter is Anna Schmidt."});
  CHECK(h.say("who is my doctor") ==
        Lines{"Sorry, I can't see anything right now: my camera is not working."});
  CHECK(h.say("who is this") ==
        Lines{"Sorry, I can't see anything right now: my camera is not working."});
}

TEST_CASE("no enrolment without a yes, with no face or with several") {
  marvin::testing::SkillHarness h(FACES_SKILL_DIR);
  h.robot().set_camera_view(kStranger);
  CHECK(h.say("remember this face as bob", {"no"}) ==
        Lines{"Shall I remember this face as Bob?", "OK, I won't remember it."});
  h.robot().set_camera_view(R"({"faces":[]})");
  // Nobody, or two, in view: not asked at all (there is no one face to consent to).
  CHECK(h.say("this is bob") == Lines{"I don't see a face. Please look at me and try again."});
  h.robot().set_camera_view(
      R"({"faces":[{"name":"","box":[0,0,10,10]},{"name":"Anna","box":[50,0,10,10]}]})");
  CHECK(h.say("this is bob") ==
        Lines{"I see more than one face. Please let Bob stand alone in front of me."});
  CHECK(h.say("who do you see") == Lines{"I see Anna and someone I don't know."});
  CHECK(h.robot().enrolled_faces().empty());
}

TEST_CASE("what do you see; a camera that fails is said plainly") {
  marvin::testing::SkillHarness h(FACES_SKILL_DIR);
  h.robot().set_camera_view(
      R"({"faces":[{"name":"","box":[0,0,10,10]},{"name":"","box":[50,0,10,10]}],
          "objects":[{"label":"cup","box":[1,2,3,4],"score":0.9}]})");
  CHECK(h.say("what do you see") == Lines{"I see a cup and two people I don't know."});
  // Pointing at something, or holding it up: the same look.
  for (const char* asked : {"what's that on the table", "what is this", "what am i holding",
                            "can you see anything", "what are those"}) {
    CAPTURE(asked);
    CHECK(h.intent_of(asked) == "faces/what_do_you_see");
  }
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

TEST_CASE("what do you see: things by the names people use, counted, then the people") {
  marvin::testing::SkillHarness h(FACES_SKILL_DIR);
  // As vision_look reports them: COCO things with spoken labels, most confident first.
  h.robot().set_camera_view(R"({"faces":[{"name":"Anna","box":[300,40,80,80]}],
      "objects":[{"label":"cup","class":"cup","box":[1,2,3,4],"score":0.9},
                 {"label":"person","class":"person","box":[280,20,200,400],"score":0.8},
                 {"label":"chair","class":"chair","box":[10,200,90,120],"score":0.7},
                 {"label":"remote control","class":"remote","box":[5,5,20,8],"score":0.6},
                 {"label":"chair","class":"chair","box":[500,200,90,120],"score":0.5},
                 {"label":"apple","class":"apple","box":[9,9,9,9],"score":0.4}]})");
  CHECK(h.say("what do you see") ==
        Lines{"I see a cup, two chairs, a remote control, an apple and Anna."});
  CHECK(h.say("what's in front of you") ==
        Lines{"I see a cup, two chairs, a remote control, an apple and Anna."});
  // Someone seen from behind (a person, no face) is said; nobody is counted twice.
  h.robot().set_camera_view(R"({"faces":[],
      "objects":[{"label":"person","box":[1,2,3,4]},{"label":"phone","box":[1,2,3,4]}]})");
  CHECK(h.say("what can you see") == Lines{"I see a phone and a person."});
  h.robot().set_camera_view(R"({"faces":[{"name":"","box":[0,0,9,9]}],
      "objects":[{"label":"person","box":[0,0,9,9]},{"label":"person","box":[50,0,9,9]},
                 {"label":"person","box":[90,0,9,9]},{"label":"knife","box":[1,2,3,4]},
                 {"label":"knife","box":[1,2,3,4]}]})");
  CHECK(h.say("what do you see") ==
        Lines{"I see two knives, two other people and someone I don't know."});
  h.robot().set_camera_view(R"({"faces":[],"objects":[]})");
  CHECK(h.say("what do you see") == Lines{"I don't see anything I know."});
}

TEST_CASE("do you see a phone; is there a cup: the things by the names people use") {
  marvin::testing::SkillHarness h(FACES_SKILL_DIR);
  h.robot().set_camera_view(R"({"faces":[{"name":"Anna","box":[300,40,80,80]}],
      "objects":[{"label":"phone","class":"cell phone","box":[1,2,3,4],"score":0.6},
                 {"label":"chair","class":"chair","box":[10,200,90,120],"score":0.7},
                 {"label":"chair","class":"chair","box":[500,200,90,120],"score":0.5}]})");
  CHECK(h.say("do you see a phone") == Lines{"Yes, I see a phone."});
  CHECK(h.say("is there a cup") == Lines{"No, I don't see a cup."});
  CHECK(h.say("can you see any chair") == Lines{"Yes, I see two chairs."});
  CHECK(h.say("is there an apple") == Lines{"No, I don't see an apple."});
  CHECK(h.say("do you see a person") == Lines{"Yes, I see a person."});
  CHECK(h.say("do you see a remote control") == Lines{"No, I don't see a remote control."});
}
