// The phone skill with the MockRobot's scripted telephone: what it says and what it dials.
// (Real calls between two baresip user agents: tests/telephony, and `marvin run --sim` in
// tests/telephony/phone_run_test.cpp.)
#include <doctest/doctest.h>

#include <marvin/testing/mock_robot.hpp>
#include <marvin/testing/skill_harness.hpp>

using Lines = std::vector<std::string>;

namespace {

void contacts(marvin::testing::SkillHarness& h) {
  auto& r = h.robot();
  r.add_contact_json(R"({"name": "Anna Schmidt", "relation": "daughter", "aliases": ["Annie"],
                         "sip_uris": ["sip:anna@127.0.0.1"], "emergency_order": 1})");
  r.add_contact_json(R"({"name": "Doctor Brown", "relation": "doctor",
                         "phone_numbers": ["0301 555 0100"], "emergency_order": 2})");
  r.add_contact_json(R"({"name": "Tom Schmidt", "relation": "son"})");
  r.add_contact_json(R"({"name": "Anna Berg", "relation": "neighbour",
                         "sip_uris": ["sip:berg@127.0.0.1"]})");
}

Lines dialled(marvin::testing::SkillHarness& h) {
  Lines out;
  for (const std::string& a : h.robot().actions()) {
    if (a.rfind("phone_", 0) == 0) out.push_back(a);
  }
  return out;
}

}  // namespace

TEST_CASE("call my daughter: confirm, ringing, connected; hang up ends the call") {
  marvin::testing::SkillHarness h(PHONE_SKILL_DIR);
  contacts(h);
  CHECK(h.intent_of("call my daughter") == "phone/call");
  CHECK(h.say("call my daughter", {"yes"}) ==
        Lines{"Call Anna Schmidt?", "Ringing Anna Schmidt.", "You're connected to Anna Schmidt."});
  CHECK(dialled(h) == Lines{"phone_dial sip:anna@127.0.0.1"});
  CHECK(h.robot().phone_state() == "in_call");
  CHECK(h.intent_of("hang up") == "phone/hang_up");
  CHECK(h.say("hang up") == Lines{"OK, I hung up. The call with Anna Schmidt has ended."});
  CHECK(h.robot().phone_state() == "idle");
  CHECK(h.say("hang up") == Lines{"There is no call to hang up."});
}

TEST_CASE("ring the doctor (a phone number), phone Annie, call a number") {
  marvin::testing::SkillHarness h(PHONE_SKILL_DIR);
  contacts(h);
  CHECK(h.intent_of("ring the doctor") == "phone/call");
  CHECK(h.say("ring the doctor", {"yes please"}).front() ==
        "Call Doctor Brown on 0301 555 0100?");
  CHECK(dialled(h) == Lines{"phone_dial 0301 555 0100"});
  h.say("end the call");
  h.robot().clear();
  CHECK(h.say("phone Annie", {"yes"}).back() == "You're connected to Anna Schmidt.");
  h.say("hang up");
  h.robot().clear();
  CHECK(h.intent_of("call 0123 456 789") == "phone/call");
  CHECK(h.say("call 0123 456 789", {"yes"}) ==
        Lines{"Call 0123 456 789?", "Ringing 0123 456 789.", "You're connected to 0123 456 789."});
  h.say("hang up");
  // The doctor's number said aloud is the doctor.
  CHECK(h.say("call 0301 555 0100", {"yes"}) ==
        Lines{"Call Doctor Brown on 0301 555 0100?", "Ringing Doctor Brown.",
              "You're connected to Doctor Brown."});
}

TEST_CASE("call Anna back, my son on his mobile: whom to call, without how or when") {
  marvin::testing::SkillHarness h(PHONE_SKILL_DIR);
  contacts(h);
  CHECK(h.say("call annie back", {"no"}) == Lines{"Call Anna Schmidt?", "OK, I won't call."});
  CHECK(h.say("ring the doctor again", {"no"}).front() == "Call Doctor Brown on 0301 555 0100?");
  CHECK(h.say("call my daughter on her mobile", {"no"}).front() == "Call Anna Schmidt?");
  CHECK(h.say("call annie at her home number", {"no"}).front() == "Call Anna Schmidt?");
  CHECK(dialled(h).empty());
  // Two Annas: "back" does not say which.
  CHECK(h.say("call anna back", {"Anna Berg", "no"}) ==
        Lines{"Do you mean Anna Berg or Anna Schmidt?", "Call Anna Berg?", "OK, I won't call."});
}

TEST_CASE("busy, not answering, failed; no means no") {
  marvin::testing::SkillHarness h(PHONE_SKILL_DIR);
  contacts(h);
  h.robot().set_call_outcome("sip:anna@127.0.0.1", "busy");
  CHECK(h.say("call my daughter", {"yes"}).back() ==
        "The line is busy. Anna Schmidt can't take the call now.");
  CHECK(h.robot().phone_state() == "idle");
  h.robot().set_call_outcome("sip:anna@127.0.0.1", "no_answer");
  CHECK(h.say("call my daughter", {"yes"}).back() == "Anna Schmidt is not answering.");
  h.robot().set_call_outcome("sip:anna@127.0.0.1", "fail");
  CHECK(h.say("call my daughter", {"yes"}).back() ==
        "I couldn't reach Anna Schmidt (503 Service Unavailable).");
  h.robot().clear();
  CHECK(h.say("call my daughter", {"no"}) == Lines{"Call Anna Schmidt?", "OK, I won't call."});
  CHECK(dialled(h).empty());
}

TEST_CASE("two Annas: asks which; unknown people and contacts without a number") {
  marvin::testing::SkillHarness h(PHONE_SKILL_DIR);
  contacts(h);
  CHECK(h.say("call Anna", {"Anna Berg", "yes"}) ==
        Lines{"Do you mean Anna Berg or Anna Schmidt?", "Call Anna Berg?", "Ringing Anna Berg.",
              "You're connected to Anna Berg."});
  h.say("hang up");
  h.robot().clear();
  CHECK(h.say("call Anna", {"the doctor"}) ==
        Lines{"Do you mean Anna Berg or Anna Schmidt?", "Sorry, I still don't know whom you mean."});
  // Slots arrive as heard, in lower case (the voice does not care).
  CHECK(h.say("call Fred") == Lines{"I don't know anyone called fred."});
  CHECK(h.say("call my son") == Lines{"I have no number for Tom Schmidt."});
  CHECK(dialled(h).empty());
}

TEST_CASE("incoming call: answer, decline; nobody calling") {
  marvin::testing::SkillHarness h(PHONE_SKILL_DIR);
  contacts(h);
  CHECK(h.say("answer") == Lines{"Nobody is calling."});
  h.robot().incoming_call("sip:anna@127.0.0.1", "Anna Schmidt");
  CHECK(h.intent_of("answer the call") == "phone/answer");
  CHECK(h.say("answer the call") == Lines{"You're connected to Anna Schmidt."});
  CHECK(h.robot().phone_state() == "in_call");
  h.robot().remote_hang_up();
  h.robot().incoming_call("sip:0301555@127.0.0.1");
  CHECK(h.intent_of("decline") == "phone/decline");
  CHECK(h.say("decline") == Lines{"I declined the call from sip:0301555@127.0.0.1."});
  CHECK(h.robot().phone_state() == "idle");
  CHECK(dialled(h) == Lines{"phone_answer", "phone_decline"});
}

TEST_CASE("call for help: no question, the emergency contacts in order, each step logged") {
  marvin::testing::SkillHarness h(PHONE_SKILL_DIR);
  contacts(h);
  h.robot().set_call_outcome("sip:anna@127.0.0.1", "no_answer");
  CHECK(h.intent_of("call for help") == "phone/emergency");
  CHECK(h.intent_of("help me") == "phone/emergency");
  CHECK(h.say("call for help") ==
        Lines{"Calling Anna Schmidt for help.", "Anna Schmidt did not answer (no answer).",
              "Calling Doctor Brown for help.", "Doctor Brown answered the emergency call.",
              "You're connected to Doctor Brown."});
  CHECK(h.robot().asked().empty());
  CHECK(h.robot().logged_events() ==
        Lines{"emergency: Calling Anna Schmidt for help",
              "emergency: Anna Schmidt did not answer (no answer)",
              "emergency: Calling Doctor Brown for help",
              "emergency: Doctor Brown answered the emergency call"});
  h.say("hang up");
  h.robot().set_call_outcome("0301 555 0100", "busy");
  CHECK(h.say("emergency").back() == "Nobody answered the emergency call.");
}

TEST_CASE("call an ambulance, phone the police: the emergency contacts, unless saved as one") {
  marvin::testing::SkillHarness h(PHONE_SKILL_DIR);
  contacts(h);
  const Lines help = {"I can't call an ambulance myself, so I'm calling your emergency contacts.",
                      "Calling Anna Schmidt for help.", "Anna Schmidt answered the emergency call.",
                      "You're connected to Anna Schmidt."};
  CHECK(h.say("call an ambulance") == help);
  CHECK(h.robot().asked().empty());
  h.say("hang up");
  CHECK(h.say("phone the emergency services").front() ==
        "I can't call the emergency services myself, so I'm calling your emergency contacts.");
  h.say("hang up");
  // The owner saved the police as a contact: that number, at once.
  h.robot().add_contact_json(R"({"name": "Police", "phone_numbers": ["110"]})");
  h.robot().clear();
  h.say("call the police");
  CHECK(dialled(h).front() == "phone_dial 110");
  CHECK(h.robot().asked().empty());
}

TEST_CASE("a fall, a stroke, smoke or gas said as it is: the emergency call, no question") {
  marvin::testing::SkillHarness h(PHONE_SKILL_DIR);
  contacts(h);
  for (const char* said : {"I fell in the bathroom", "I think I'm having a stroke",
                           "there's smoke in the kitchen", "I smell gas"}) {
    CAPTURE(said);
    CHECK(h.intent_of(said) == "phone/emergency");
    CHECK(h.say(said).front() == "Calling Anna Schmidt for help.");
    CHECK(h.robot().asked().empty());
    h.say("hang up");
  }
}

TEST_CASE("did anyone call: the last day's calls from the event log, missed ones first") {
  marvin::testing::SkillHarness h(PHONE_SKILL_DIR);
  contacts(h);
  auto& r = h.robot();
  constexpr std::int64_t kHour = 60 * 60 * 1000;
  const std::int64_t t0 = 1767600000000;  // 2026-01-05T08:00Z
  r.set_now(t0);
  CHECK(h.intent_of("did anyone call") == "phone/calls");
  CHECK(h.say("did anyone call") == Lines{"Nobody called in the last day."});
  r.add_event("call_incoming", "Doctor Brown is calling");  // more than a day before the question
  r.add_event("call_missed", "You missed a call from Doctor Brown.");
  r.set_now(t0 + 30 * kHour);
  r.add_event("call_incoming", "Anna Schmidt is calling");
  r.add_event("call_missed", "You missed a call from Anna Schmidt.");
  r.set_now(t0 + 32 * kHour);
  r.add_event("call_incoming", "Tom Schmidt is calling");  // taken: no call_missed after it
  r.set_now(t0 + 32 * kHour + 10 * 60 * 1000);
  CHECK(
      h.say("who called me") ==
      Lines{"You missed a call from Anna Schmidt 2 hours ago. Tom Schmidt called 10 minutes ago."});
  CHECK(
      h.say("did I miss any calls") ==
      Lines{"You missed a call from Anna Schmidt 2 hours ago. Tom Schmidt called 10 minutes ago."});
  CHECK(dialled(h).empty());
}

TEST_CASE("I don't feel well: asks before calling for help; good news is only answered") {
  marvin::testing::SkillHarness h(PHONE_SKILL_DIR);
  contacts(h);
  CHECK(h.intent_of("I don't feel well") == "phone/unwell");
  CHECK(
      h.say("I'm not feeling well", {"no, I'll be fine"}) ==
      Lines{"I'm sorry you're not feeling well. Shall I call for help?",
            "OK. If you feel worse, say \"call for help\" and I'll call your emergency contacts."});
  CHECK(dialled(h).empty());
  CHECK(h.say("I don't feel well", {"yes please"}) ==
        Lines{"I'm sorry you're not feeling well. Shall I call for help?",
              "Calling Anna Schmidt for help.", "Anna Schmidt answered the emergency call.",
              "You're connected to Anna Schmidt."});
  h.say("hang up");
  h.robot().clear();
  // Naming someone calls them, without asking again.
  CHECK(h.say("I feel dizzy", {"yes, call Doctor Brown"}) ==
        Lines{"I'm sorry you're not feeling well. Shall I call for help?", "Ringing Doctor Brown.",
              "You're connected to Doctor Brown."});
  CHECK(dialled(h) == Lines{"phone_dial 0301 555 0100"});
  h.say("hang up");
  h.robot().clear();
  // The model hears "I feel great" as this intent (it weighs words, not their order): no
  // question, nothing dialled.
  REQUIRE(h.intent_of("I feel great today") == "phone/unwell");
  CHECK(h.say("I feel great today") == Lines{"I'm glad to hear that."});
  CHECK(h.robot().asked().empty());
  CHECK(dialled(h).empty());
}

TEST_CASE("a pain or an illness said as it is: the same offer to call for help") {
  marvin::testing::SkillHarness h(PHONE_SKILL_DIR);
  contacts(h);
  for (const char* said : {"I have a pain in my chest", "I've got a bad headache", "my back hurts",
                           "I'm in pain", "I have a temperature"}) {
    CAPTURE(said);
    CHECK(h.intent_of(said) == "phone/unwell");
    CHECK(h.say(said, {"no"}).front() == "I'm sorry you're not feeling well. Shall I call for help?");
  }
  CHECK(dialled(h).empty());
  CHECK(h.say("my chest hurts", {"yes"}).at(1) == "Calling Anna Schmidt for help.");
  h.say("hang up");
  h.robot().clear();
  // Neither good nor bad news in words the skill knows: asked, not congratulated.
  for (const char* said : {"I slipped", "I cut my finger", "I need a doctor"}) {
    CAPTURE(said);
    CHECK(h.intent_of(said) == "phone/unwell");
    CHECK(h.say(said, {"no"}).front() == "I'm sorry you're not feeling well. Shall I call for help?");
  }
  CHECK(dialled(h).empty());
}

TEST_CASE("I'm lonely: offers to call someone, asks whom; no or an answer naming no one") {
  marvin::testing::SkillHarness h(PHONE_SKILL_DIR);
  contacts(h);
  CHECK(h.intent_of("I feel lonely") == "phone/lonely");
  CHECK(h.say("I'm so lonely", {"yes", "my daughter"}) ==
        Lines{"I'm sorry to hear that. Shall I call someone for you?", "Whom should I call?",
              "Ringing Anna Schmidt.", "You're connected to Anna Schmidt."});
  CHECK(dialled(h) == Lines{"phone_dial sip:anna@127.0.0.1"});
  h.say("hang up");
  h.robot().clear();
  // Someone missed by name: offered a call to them.
  CHECK(h.say("I miss my daughter", {"yes please"}) ==
        Lines{"I'm sure you do. Shall I call Anna Schmidt for you?", "Ringing Anna Schmidt.",
              "You're connected to Anna Schmidt."});
  h.say("hang up");
  h.robot().clear();
  CHECK(h.say("I miss my son", {"no"}) ==
        Lines{"I'm sure you do. Shall I call Tom Schmidt for you?", "OK. I'm here if you need me."});
  CHECK(h.say("I'm scared", {"no"}) ==
        Lines{"I'm sorry to hear that. Shall I call someone for you?", "OK. I'm here if you need me."});
  CHECK(dialled(h).empty());
  for (const char* answer : {"no thanks", "I'm fine", "not really"}) {
    CAPTURE(answer);
    CHECK(h.say("I feel lonely", {answer}) ==
          Lines{"I'm sorry to hear that. Shall I call someone for you?",
                "OK. I'm here if you need me."});
  }
  CHECK(dialled(h).empty());
}

TEST_CASE("I want to talk to Anna: a call; to you: no call; to someone: asks whom") {
  marvin::testing::SkillHarness h(PHONE_SKILL_DIR);
  contacts(h);
  for (const char* request : {"I want to talk to Annie", "I'd like to speak to my daughter",
                              "can I talk to Anna Schmidt please", "let me speak with my daughter",
                              "put me through to Annie"}) {
    CAPTURE(request);
    CHECK(h.intent_of(request) == "phone/call");
    CHECK(h.say(request, {"yes"}) == Lines{"Call Anna Schmidt?", "Ringing Anna Schmidt.",
                                           "You're connected to Anna Schmidt."});
    h.say("hang up");
  }
  h.robot().clear();
  for (const char* request : {"I want to talk to you", "can I speak to you for a moment"}) {
    CAPTURE(request);
    CHECK(h.say(request) == Lines{"I'm listening. What can I do for you?"});
  }
  CHECK(h.say("I need to talk to someone", {"nobody"}) ==
        Lines{"Whom should I call?", "OK. I'm here if you need me."});
  CHECK(dialled(h).empty());
  CHECK(h.say("I need to talk to someone", {"my daughter please"}) ==
        Lines{"Whom should I call?", "Ringing Anna Schmidt.", "You're connected to Anna Schmidt."});
  CHECK(dialled(h) == Lines{"phone_dial sip:anna@127.0.0.1"});
}

TEST_CASE("bad input: no telephone, a refused registration, no emergency contact") {
  marvin::testing::SkillHarness h(PHONE_SKILL_DIR);
  CHECK(h.say("call for help") ==
        Lines{"I have no emergency contact to call. Add one with marvin contacts add "
              "--emergency 1."});
  contacts(h);
  h.robot().set_phone_failure("sip.example.org refused the registration (403 Forbidden)");
  CHECK(h.say("call my daughter", {"yes"}).back() ==
        "I can't make the call: sip.example.org refused the registration (403 Forbidden).");
  CHECK(h.robot().phone_state() == "idle");
  h.robot().set_phone_available(false);
  CHECK(h.say("call my daughter") == Lines{"I can't make the call: this robot has no telephone."});
  CHECK(h.robot().logged_events().empty());
}

TEST_CASE("the Robot API's phone calls need the 'phone' permission and change nothing without") {
  marvin::testing::MockRobot robot("nophone", {"contacts"});
  const marvin_robot_api* api = robot.api();
  CHECK(api->minor >= 3);
  CHECK(api->phone_dial(robot.host(), "sip:anna@127.0.0.1", "Anna") == MARVIN_ERR_PERMISSION);
  CHECK(std::string(api->last_error(robot.host())) ==
        "permission 'phone' is not granted to skill 'nophone'");
  CHECK(api->phone_call_for_help(robot.host()) == MARVIN_ERR_PERMISSION);
  CHECK(api->phone_call(robot.host(), "0123") == MARVIN_ERR_PERMISSION);
  CHECK(robot.actions().empty());
  CHECK(robot.phone_state() == "idle");
  robot.set_permissions({"phone"});
  CHECK(api->phone_dial(robot.host(), nullptr, "") == MARVIN_ERR_INVALID);
  CHECK(std::string(api->last_error(robot.host())) == "number is NULL");
  CHECK(api->phone_hang_up(robot.host()) == MARVIN_ERR_NOT_FOUND);
  CHECK(std::string(api->last_error(robot.host())) == "there is no call to hang up");
  char buffer[8];
  marvin_text_out small{buffer, sizeof buffer, 0};
  CHECK(api->phone_state(robot.host(), &small) == MARVIN_ERR_TRUNCATED);
  // The 1.0 call dials for real since 1.3.
  CHECK(api->phone_call(robot.host(), "0123 456") == MARVIN_OK);
  CHECK(robot.actions() == Lines{"phone_dial 0123 456"});
  CHECK(robot.phone_state() == "in_call");
}
