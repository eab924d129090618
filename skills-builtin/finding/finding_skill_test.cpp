// The finding skill through the SkillHarness, with the MockRobot's rooms and per-room views.
#include <doctest/doctest.h>

#include <marvin/testing/skill_harness.hpp>

using Lines = std::vector<std::string>;

namespace {

std::string joined(const std::vector<std::string>& v) {
  std::string out;
  for (const auto& s : v) out += s + " | ";
  return out;
}

const char* kAnna = R"({"faces":[{"name":"Anna","box":[300,200,60,60]}],"objects":[]})";
const char* kStranger = R"({"faces":[{"name":"","box":[300,200,60,60]}],"objects":[]})";
const char* kKeys = R"({"faces":[],"objects":[{"label":"keys","box":[300,300,40,30]}]})";

void home(marvin::testing::SkillHarness& h) {
  for (const char* room : {"hall", "kitchen", "bedroom", "living room"}) h.robot().add_place(room, room);
  h.robot().add_place("Anna", "living room");
}

}  // namespace

TEST_CASE("find Anna: searches the rooms, the map's room for her first, and reports the room") {
  marvin::testing::SkillHarness h(FINDING_SKILL_DIR);
  home(h);
  h.robot().set_room_view("kitchen", kAnna);  // she is not where the map last saw her
  CHECK(h.say("find anna") ==
        Lines{"I'll look for Anna.", "Anna is in the kitchen."});
  // Now from memory, without moving.
  h.robot().clear();
  CHECK(h.say("where is anna", {"no"}) ==
        Lines{"I saw Anna in the kitchen, just now.", "Shall I look again?"});
  // "is Anna home" asks the same (it once turned guard mode off: "Welcome home!").
  CHECK(h.intent_of("is Anna home") == "finding/where_is");
  CHECK(h.say("is Anna home", {"no"}) ==
        Lines{"I saw Anna in the kitchen, just now.", "Shall I look again?"});
  const std::string actions = joined(h.robot().actions());
  INFO(actions);
  CHECK(actions.find("go_to") == std::string::npos);
  CHECK(actions.find("turn") == std::string::npos);
}

TEST_CASE("a person on the map whose face Marvin does not know: no search, how to introduce") {
  marvin::testing::SkillHarness h(FINDING_SKILL_DIR);
  home(h);  // Anna has a place on the map, but no face was ever named or enrolled
  h.robot().set_room_view("living room", kStranger);
  const std::string unknown =
      "I don't know Anna's face yet, so I can't look for Anna. When Anna is in front of me, say "
      "\"this is Anna\".";
  CHECK(h.say("find anna") == Lines{unknown});
  CHECK(h.say("tell anna dinner is ready") == Lines{unknown});
  const std::string actions = joined(h.robot().actions());
  INFO(actions);
  CHECK(actions.find("go_to") == std::string::npos);  // no search: only the status light
  CHECK(actions.find("turn") == std::string::npos);
}

TEST_CASE("who is at the door: the robot goes to the front door and says whom it sees") {
  marvin::testing::SkillHarness h(FINDING_SKILL_DIR);
  home(h);
  CHECK(h.say("who is at the door") ==
        Lines{"I don't know where your front door is: it isn't on my map."});
  CHECK(joined(h.robot().actions()).find("go_to") == std::string::npos);
  h.robot().add_place("the front door", "hall");
  h.robot().set_room("kitchen");
  h.robot().set_room_view("hall", R"({"faces":[],"objects":[]})");
  // Nobody in view: a closed door hides whoever rang, so "nobody" is not said.
  CHECK(h.say("who is at the door") ==
        Lines{"I'm at the front door and I don't see anyone. If someone is outside, ask who it "
              "is before you open the door."});
  CHECK(joined(h.robot().actions()).find("go_to the front door") != std::string::npos);
  h.robot().set_room_view("hall", kStranger);
  CHECK(h.say("is anyone at the front door") ==
        Lines{"Yes: someone I don't know is at the front door."});
  h.robot().set_room_view("hall", kAnna);
  CHECK(h.say("there's someone at the door") == Lines{"Anna is at the front door."});
  h.robot().block_place("the front door", "a chair is in the way");
  CHECK(h.say("who is at the door") ==
        Lines{"I can't get to the front door: a chair is in the way."});
}

TEST_CASE("is anyone in the bedroom: a stranger; an unknown room is named") {
  marvin::testing::SkillHarness h(FINDING_SKILL_DIR);
  home(h);
  h.robot().set_room_view("bedroom", kStranger);
  CHECK(h.say("is anyone in the bedroom") == Lines{"Yes: someone I don't know is in the bedroom."});
  CHECK(h.say("is anyone in the kitchen") == Lines{"No, I don't see anyone in the kitchen."});
  CHECK(h.say("who is in the kitchen") == Lines{"I don't see anyone in the kitchen."});
  CHECK(h.say("is anyone in the garage") == Lines{"I don't know a room called the garage."});
}

TEST_CASE("is anyone home: every room in turn; is anyone here: this room, without moving") {
  marvin::testing::SkillHarness h(FINDING_SKILL_DIR);
  home(h);
  h.robot().set_room_view("kitchen", kAnna);
  h.robot().set_room_view("bedroom", kStranger);
  // Templates that fit equally well go to the intent the model prefers: "in the house" is
  // no thing to look for (once: "I don't know who or what there someone is.").
  CHECK(h.intent_of("is there someone in the house") == "finding/anyone_in");
  const Lines everyone = {"I'll have a look around the house.",
                          "Yes: Anna is in the kitchen and someone I don't know is in the "
                          "bedroom."};
  CHECK(h.say("is anyone home") == everyone);
  CHECK(h.say("is there someone in the house") == everyone);
  // "who ...?" is answered with the people, without "Yes:" (the rooms in the order searched).
  const Lines who = h.say("who is home");
  REQUIRE(who.size() == 2);
  CHECK(who[1] == "Someone I don't know is in the bedroom and Anna is in the kitchen.");
  h.robot().block_place("bedroom", "the door is closed");
  CHECK(h.say("is anybody there") ==
        Lines{"I'll have a look around the house.",
              "Yes: Anna is in the kitchen. I couldn't get into the bedroom."});
  h.robot().set_room("kitchen");
  h.robot().clear();
  CHECK(h.say("is anyone here") == Lines{"Yes: Anna is here with us."});
  CHECK(h.say("who is in the room") == Lines{"Anna is here with us."});
  CHECK(h.say("is anyone in here") == Lines{"Yes: Anna is here with us."});
  CHECK(h.robot().room() == "kitchen");
  CHECK(joined(h.robot().actions()).find("go_to") == std::string::npos);
  h.robot().set_room("hall");
  CHECK(h.say("is there somebody in here") == Lines{"No, I don't see anyone here."});
}

TEST_CASE("tell Anna dinner is ready: goes to her and says it; nobody called Bob") {
  marvin::testing::SkillHarness h(FINDING_SKILL_DIR);
  home(h);
  h.robot().set_room_view("living room", kAnna);
  CHECK(h.say("tell anna dinner is ready") ==
        Lines{"I'll tell Anna.", "Anna, dinner is ready."});
  CHECK(h.robot().room() == "living room");
  CHECK(h.say("tell bob dinner is ready") == Lines{"I don't know anyone called Bob."});
  CHECK(h.say("find bob") == Lines{"I don't know who or what bob is."});
  // A contact whose face Marvin does not know: no search, how to introduce them.
  h.robot().add_contact_json(R"({"name": "Tom", "relation": "son"})");
  CHECK(h.say("where is tom") ==
        Lines{"I don't know Tom's face yet, so I can't look for Tom. When Tom is in front of me, "
              "say \"this is Tom\"."});
  CHECK(h.robot().room() == "living room");  // it did not go looking
  // "my son" is Tom, by the contact's relation (before: a thing called "son").
  CHECK(h.say("where is my son") ==
        Lines{"I don't know Tom's face yet, so I can't look for Tom. When Tom is in front of me, "
              "say \"this is Tom\"."});
  CHECK(h.say("tell my son lunch is ready") ==
        Lines{"I don't know Tom's face yet, so I can't look for Tom. When Tom is in front of me, "
              "say \"this is Tom\"."});
  CHECK(h.say("where is my wife") ==
        Lines{"I don't know who your wife is. To tell me, say \"add a contact\"."});
}

TEST_CASE("where are my keys: search, report, lead the way; never seen and never taught") {
  marvin::testing::SkillHarness h(FINDING_SKILL_DIR);
  home(h);
  for (const char* lost : {"I lost my keys", "I've misplaced my keys", "I can't find my keys"}) {
    CAPTURE(lost);
    CHECK(h.intent_of(lost) == "finding/where_is");
  }
  h.robot().set_room_view("bedroom", kKeys);
  // Seen while looking for people in the bedroom: every look records what it saw.
  CHECK(h.say("is anyone in the bedroom") == Lines{"No, I don't see anyone in the bedroom."});
  const Lines keys = h.say("where are my keys", {"no"});
  INFO(joined(keys));
  CHECK(keys == Lines{"I saw your keys in the bedroom, just now.", "Shall I look again?"});
  h.robot().set_room("hall");
  CHECK(h.say("find my keys", {"yes"}) ==
        Lines{"I'll look for your keys.", "Your keys are in the bedroom.",
              "Shall I show you the way?", "Here we are: the bedroom."});
  CHECK(h.say("have you seen my keys", {"yes", "no"}) ==
        Lines{"I saw your keys in the bedroom, just now.", "Shall I look again?",
              "I'll look for your keys.", "Your keys are in the bedroom.",
              "Shall I show you the way?"});
  // One thing is "it", several "them", in what Marvin asks to be shown.
  CHECK(h.say("where is my umbrella").back() ==
        "I don't know what your umbrella looks like, and I have never seen it. Show me and say "
        "\"this is my umbrella\".");
  CHECK(h.say("where are my slippers").back() ==
        "I don't know what your slippers look like, and I have never seen them. Show me and say "
        "\"these are my slippers\".");
  // The thing ends where the request for help starts.
  CHECK(h.say("I can't find my slippers, can you help me find them").back() ==
        "I don't know what your slippers look like, and I have never seen them. Show me and say "
        "\"these are my slippers\".");
}

TEST_CASE("where is the kitchen / the sofa: from the map, no search; the way there if wanted") {
  marvin::testing::SkillHarness h(FINDING_SKILL_DIR);
  home(h);
  h.robot().add_place("the sofa", "living room");
  h.robot().set_room("hall");
  CHECK(h.say("where is the kitchen", {"yes"}) ==
        Lines{"The kitchen is one of the rooms here; I'm in the hall.", "Shall I show you the way?",
              "Here we are: the kitchen."});
  CHECK(h.robot().room() == "kitchen");
  CHECK(h.say("where is the kitchen") == Lines{"We're in the kitchen."});
  CHECK(h.say("where's the sofa", {"no"}) ==
        Lines{"The sofa is in the living room.", "Shall I show you the way?"});
  CHECK(h.robot().room() == "kitchen");  // "no": it stayed
  // Asked for the way: the same answer, and the offer to show it.
  h.robot().set_room("hall");
  for (const char* asked : {"which way is the kitchen", "how do i get to the kitchen"}) {
    CAPTURE(asked);
    CHECK(h.say(asked, {"no"}) == Lines{"The kitchen is one of the rooms here; I'm in the hall.",
                                        "Shall I show you the way?"});
  }
}

TEST_CASE("a blocked room and a camera failure mid-search: clear speech, the rooms named") {
  marvin::testing::SkillHarness h(FINDING_SKILL_DIR);
  home(h);
  h.robot().block_place("kitchen", "the kitchen door is blocked");
  h.robot().set_room_view("kitchen", kAnna);  // known by face, behind the blocked door
  h.robot().set_room_view("hall", R"({"faces":[],"objects":[]})");
  const Lines said = h.say("find anna");
  REQUIRE(said.size() == 2);
  CHECK(said[1].find("I couldn't find Anna. I looked in the living room, the hall") == 0);
  CHECK(said[1].find("I couldn't get into the kitchen.") != std::string::npos);
  h.robot().set_camera_failure("the simulated camera: the photo anna.jpg is missing");
  const Lines broken = h.say("find anna");
  CHECK(broken.back() == "Sorry, my camera stopped working while I was looking for Anna. "
                         "I had looked in the living room.");
}

TEST_CASE("how one is, said in passing, is not about guarding the house") {
  marvin::testing::SkillHarness h(FINDING_SKILL_DIR);
  for (const char* said : {"I am really hungry", "I'm so tired today", "I'm thirsty"}) {
    CAPTURE(said);
    const Lines out = h.say(said);
    INFO(joined(out));
    REQUIRE(out.size() == 1);
    CHECK(out[0].rfind("Sorry, I don't know how to help with that.", 0) == 0);
    CHECK_FALSE(h.robot().guarding());
  }
}

TEST_CASE("guard mode: on by voice; off only for a known face; who came reads the events") {
  marvin::testing::SkillHarness h(FINDING_SKILL_DIR);
  h.robot().set_camera_view(kStranger);
  const Lines out = h.say("i'm going out");
  INFO(joined(out));
  CHECK(out.back().rfind("OK, I'm guarding the house.", 0) == 0);
  CHECK(h.robot().guarding());
  h.robot().add_event("intruder", "Intruder alert: I see someone I don't know in the hall. Photo: /x.jpg");
  CHECK(h.say("i'm home") ==
        Lines{"I can only stop guarding for someone I know. Please let me see your face."});
  CHECK(h.robot().guarding());
  h.robot().set_camera_view(kAnna);
  CHECK(h.say("i'm home") == Lines{"Welcome back, Anna. I stopped guarding."});
  CHECK_FALSE(h.robot().guarding());
  // Not guarding: a stranger coming home is greeted and nothing changes.
  h.robot().set_camera_view(kStranger);
  CHECK(h.say("i'm back") == Lines{"Welcome home!"});
  CHECK_FALSE(h.robot().guarding());
  CHECK(h.say("who came while i was out") ==
        Lines{"One visitor: someone I don't know in the hall, just now. I saved a photo of "
              "each in my data folder."});
  // Asked for the night, or for the time away, in a few words of its own.
  for (const char* watch : {"keep an eye on the house tonight", "mind the flat for me",
                            "keep watch while i'm away", "look after the home please"}) {
    CAPTURE(watch);
    CHECK(h.intent_of(watch) == "finding/guard_on");
  }
}
