// The built-in hello skill, loaded from the build tree: the courtesies and the introduction.
#include <doctest/doctest.h>

#include <marvin/testing/skill_harness.hpp>

using Lines = std::vector<std::string>;

TEST_CASE("hello, thank you and goodbye each get their own answer") {
  marvin::testing::SkillHarness harness(HELLO_SKILL_DIR);
  CHECK(harness.say("hello marvin") == Lines{"Hello! What can I do for you?"});
  CHECK(harness.say("how are you today") == Lines{"I'm fine, thank you. What can I do for you?"});
  CHECK(harness.say("can you hear me") == Lines{"Yes, I'm here. What can I do for you?"});
  CHECK(harness.say("Marvin, are you there?") == Lines{"Yes, I'm here. What can I do for you?"});
  CHECK(harness.say("thank you very much") == Lines{"You're welcome."});
  CHECK(harness.say("cheers robot") == Lines{"You're welcome."});
  CHECK(harness.say("bye for now") == Lines{"Goodbye. Just say my name when you need me."});
  CHECK(harness.say("see you tomorrow") == Lines{"Goodbye. Just say my name when you need me."});
  CHECK(harness.say("good night marvin") == Lines{"Good night. Sleep well."});
  CHECK(harness.say("goodnight Marvin") == Lines{"Good night. Sleep well."});
  CHECK(harness.say("Marvin?") == Lines{"Yes, I'm here. What can I do for you?"});
  CHECK(harness.say("OK Marvin") == Lines{"Yes, I'm here. What can I do for you?"});
  CHECK(harness.say("I'm going to bed") == Lines{"Good night. Sleep well."});
  CHECK(harness.say("time for bed") == Lines{"Good night. Sleep well."});
}

TEST_CASE("good morning is answered with the greeting of the owner's time of day") {
  marvin::testing::SkillHarness harness(HELLO_SKILL_DIR);
  harness.robot().set_time_zone("Europe/Berlin");
  harness.robot().set_now(1795269900000);  // 2026-11-21T14:05Z: 3:05 PM in Berlin
  CHECK(harness.say("good morning marvin") == Lines{"Good afternoon! What can I do for you?"});
  harness.robot().set_time_zone("America/New_York");  // 9:05 AM
  CHECK(harness.say("good evening") == Lines{"Good morning! What can I do for you?"});
  harness.robot().set_time_zone("Asia/Tokyo");  // 11:05 PM
  CHECK(harness.say("good afternoon") == Lines{"Good evening! What can I do for you?"});
  CHECK(harness.say("hello") == Lines{"Hello! What can I do for you?"});
}

TEST_CASE("what can you do: the introduction names every built-in capability") {
  marvin::testing::SkillHarness harness(HELLO_SKILL_DIR);
  const Lines answer = harness.say("what can you do");
  REQUIRE(answer.size() == 1);
  for (const char* capability :
       {"time", "reminders", "timers", "schedule", "recognise", "find people and things",
        "keep watch", "guide", "lights", "phone calls"}) {
    CAPTURE(capability);
    CHECK(answer[0].find(capability) != std::string::npos);
  }
  CHECK(harness.say("who are you") == answer);
}
