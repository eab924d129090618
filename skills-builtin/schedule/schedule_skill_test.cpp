// The schedule skill's conversations on a MockRobot: Monday 2026-01-05, 10:00 in Berlin.
#include <doctest/doctest.h>

#include <dlfcn.h>

#include <map>
#include <set>

#include <nlohmann/json.hpp>

#include <marvin/skill.h>
#include <marvin/testing/mock_robot.hpp>
#include <marvin/testing/skill_harness.hpp>

using Lines = std::vector<std::string>;
using nlohmann::json;

namespace {

// The MockRobot's clock starts at 2026-01-05T09:00Z, a Monday.
void berlin(marvin::testing::SkillHarness& h) { h.robot().set_time_zone("Europe/Berlin"); }

std::vector<json> reminders(marvin::testing::SkillHarness& h) {
  std::vector<json> out;
  for (const std::string& text : h.robot().reminders()) out.push_back(json::parse(text));
  return out;
}

}  // namespace

TEST_CASE("remind me to take my pills at 8 pm: stored, then acknowledged") {
  marvin::testing::SkillHarness h(SCHEDULE_SKILL_DIR);
  berlin(h);
  CHECK(h.say("remind me to take my pills at 8 pm") ==
        Lines{"OK, I'll remind you to take your pills today at 8 PM."});
  const auto stored = reminders(h);
  REQUIRE(stored.size() == 1);
  CHECK(stored[0]["title"] == "take my pills");
  CHECK(stored[0]["at"] == "2026-01-05T20:00");
  CHECK(stored[0]["time_zone"] == "Europe/Berlin");
}

TEST_CASE("pills twice a day: every day at 9 am and 9 pm is two reminders, said as one") {
  marvin::testing::SkillHarness h(SCHEDULE_SKILL_DIR);
  berlin(h);  // Monday 10:00
  CHECK(h.say("remind me to take my pills every day at 9 am and 9 pm") ==
        Lines{"OK, I'll remind you to take your pills every day at 9 AM and 9 PM."});
  CHECK(h.say("wake me up tomorrow at 6 and at 7") ==
        Lines{"OK, I'll wake you tomorrow at 6 AM and 7 AM."});
  CHECK(h.say("remind me to feed the cat at 8 and at 8 pm") ==
        Lines{"OK, I'll remind you to feed the cat today at 8 PM and tomorrow at 8 AM."});
  std::multiset<std::string> stored;  // title, time, recurrence of each
  for (const json& r : reminders(h)) {
    stored.insert(r["title"].get<std::string>() + " " + r["at"].get<std::string>() + " " +
                  r["recurrence"]["kind"].get<std::string>());
  }
  CHECK(stored == std::multiset<std::string>{
                      "take my pills 2026-01-06T09:00 daily", "take my pills 2026-01-05T21:00 daily",
                      "time to wake up 2026-01-06T06:00 once", "time to wake up 2026-01-06T07:00 once",
                      "feed the cat 2026-01-06T08:00 once", "feed the cat 2026-01-05T20:00 once"});
}

TEST_CASE("names in a reminder keep their capitals: as typed, or as in the address book") {
  marvin::testing::SkillHarness h(SCHEDULE_SKILL_DIR);
  berlin(h);
  h.robot().add_contact_json(R"({"name": "Doctor Brown", "relation": "doctor"})");
  h.robot().add_contact_json(R"({"name": "Tom", "relation": "son"})");
  // Speech comes in lower case: the address book spells the names.
  CHECK(h.say("remind me to call tom at 5 pm") ==
        Lines{"OK, I'll remind you to call Tom today at 5 PM."});
  CHECK(h.say("remind me to ring doctor brown tomorrow") ==
        Lines{"OK, I'll remind you to ring Doctor Brown tomorrow at 9 AM."});
  // A title alone is no name; "I" is said back as "you".
  CHECK(h.say("remind me to call the doctor when I get home at 6 pm") ==
        Lines{"OK, I'll remind you to call the doctor when you get home today at 6 PM."});
  // Typed with a capital: kept.
  CHECK(h.say("Remind me to visit Margaret at 3 pm") ==
        Lines{"OK, I'll remind you to visit Margaret today at 3 PM."});
  bool stored = false;
  for (const json& r : reminders(h)) stored = stored || r["title"] == "call Tom";
  CHECK(stored);
}

TEST_CASE("don't let me forget the bins: a thing is said back \"about\"; anything on tomorrow") {
  marvin::testing::SkillHarness h(SCHEDULE_SKILL_DIR);
  berlin(h);  // Monday 10:00
  CHECK(h.say("don't let me forget the bins on thursday") ==
        Lines{"OK, I'll remind you about the bins on Thursday, 8 January at 9 AM."});
  CHECK(h.say("remind me to put the bins out tomorrow at 7 pm") ==
        Lines{"OK, I'll remind you to put the bins out tomorrow at 7 PM."});
  CHECK(h.say("anything on tomorrow?") == Lines{"Tomorrow: put the bins out at 7 PM."});
  CHECK(reminders(h).size() == 2);
}

TEST_CASE("an alarm needs no task: wake me at 6 is 6 in the morning, and stored") {
  marvin::testing::SkillHarness h(SCHEDULE_SKILL_DIR);
  berlin(h);  // Monday 10:00
  CHECK(h.say("wake me up tomorrow at 6") == Lines{"OK, I'll wake you tomorrow at 6 AM."});
  CHECK(h.say("set an alarm for 7 every day") == Lines{"OK, I'll wake you every day at 7 AM."});
  // Asked when, the answer is read as the request meant it: 6:30 in the morning.
  CHECK(
      h.say("set an alarm", {"6:30 on wednesday"}) ==
      Lines{"When should I remind you?", "OK, I'll wake you on Wednesday, 7 January at 6:30 AM."});
  const auto stored = reminders(h);
  REQUIRE(stored.size() == 3);
  CHECK(stored[0]["title"] == "time to wake up");
  CHECK(stored[0]["at"] == "2026-01-06T06:00");
  CHECK(stored[1]["recurrence"]["kind"] == "daily");
  CHECK(stored[1]["at"] == "2026-01-06T07:00");  // 7 today has passed
  CHECK(stored[2]["at"] == "2026-01-07T06:30");
  // Alarms are "time to wake up" when stored; "cancel my alarms" finds them all.
  CHECK(h.say("cancel my alarms", {"yes"}).back() == "OK, I cancelled all 3 reminders.");
  CHECK(reminders(h).empty());
  h.say("wake me up at 6");
  CHECK(h.say("cancel my alarm") == Lines{"OK, I cancelled the alarm."});
  CHECK(reminders(h).empty());
}

TEST_CASE("turn off the alarm: the alarm set, the one that just rang, or none") {
  marvin::testing::SkillHarness h(SCHEDULE_SKILL_DIR);
  berlin(h);
  h.say("remind me to call the bank at 5 pm");
  CHECK(h.say("stop the alarm") == Lines{"You have no alarm set."});
  CHECK(reminders(h).size() == 1);  // the bank is no alarm
  h.say("wake me up tomorrow at 6");
  CHECK(h.say("turn off my alarm") == Lines{"OK, I cancelled the alarm."});
  REQUIRE(reminders(h).size() == 1);
  CHECK(reminders(h)[0]["title"] == "call the bank");
  // An alarm that has rung and is over (here marked done): stopping it is no error.
  h.say("wake me up tomorrow at 6");
  h.robot().set_last_fired(reminders(h).at(1)["id"].get<std::int64_t>());
  h.say("done");
  CHECK(h.say("silence the alarm") == Lines{"OK, the alarm is off."});
  CHECK(h.say("cancel a reminder", {"dentist"}) ==
        Lines{"Which reminder should I cancel?", "I couldn't find a reminder about dentist."});
}

TEST_CASE("a reminder said without its task: the skill asks for it; no answer, nothing stored") {
  marvin::testing::SkillHarness h(SCHEDULE_SKILL_DIR);
  berlin(h);
  CHECK(h.say("set a reminder for tomorrow at 9", {"To call the bank."}) ==
        Lines{"What should I remind you of?",
              "OK, I'll remind you to call the bank tomorrow at 9 AM."});
  CHECK(h.say("set a reminder for tomorrow at 10", {"..."}) ==
        Lines{"What should I remind you of?",
              "Sorry, I didn't get what to remind you of. Let's leave it for now."});
  const auto stored = reminders(h);
  REQUIRE(stored.size() == 1);
  CHECK(stored[0]["title"] == "call the bank");
}

TEST_CASE("remind me every day at 9 to water the plants; what's on my schedule") {
  marvin::testing::SkillHarness h(SCHEDULE_SKILL_DIR);
  berlin(h);
  CHECK(h.say("remind me every day at 9 to water the plants") ==
        Lines{"OK, I'll remind you to water the plants every day at 9 AM."});
  const auto stored = reminders(h);
  REQUIRE(stored.size() == 1);
  CHECK(stored[0]["recurrence"]["kind"] == "daily");
  CHECK(stored[0]["at"] == "2026-01-06T09:00");  // 9 today has passed
  h.say("remind me to take my pills at 8 pm");
  CHECK(h.say("what's on my schedule tomorrow") == Lines{"Tomorrow: water the plants at 9 AM."});
  CHECK(h.say("what's on my schedule") == Lines{"Today: take your pills at 8 PM."});
  // The list says how a reminder repeats, not only when it rings next.
  CHECK(h.say("what are my reminders") ==
        Lines{"You have 2 reminders: take your pills today at 8 PM and water the plants every "
              "day at 9 AM."});
}

TEST_CASE("what do i have next week / this week / this weekend: each day with something") {
  marvin::testing::SkillHarness h(SCHEDULE_SKILL_DIR);
  berlin(h);  // Monday 2026-01-05
  h.say("remind me every tuesday at 10 to go swimming");
  h.say("remind me tomorrow at 3 pm to buy milk");
  CHECK(h.say("what do i have next week") ==
        Lines{"On Tuesday, 13 January: go swimming at 10 AM."});
  CHECK(h.say("what's on my calendar this week") ==
        Lines{"Tomorrow: go swimming at 10 AM and buy milk at 3 PM."});
  CHECK(h.say("what's on my schedule this weekend") ==
        Lines{"You have nothing on your schedule from Saturday, 10 January to Sunday, 11 January."});
}

TEST_CASE("cancel the pill reminder: only the matching one goes") {
  marvin::testing::SkillHarness h(SCHEDULE_SKILL_DIR);
  berlin(h);
  h.say("remind me to take my pills at 8 pm");
  h.say("remind me every day at 9 to water the plants");
  CHECK(h.say("cancel the pill reminder") ==
        Lines{"OK, I cancelled the reminder to take your pills."});
  const auto stored = reminders(h);
  REQUIRE(stored.size() == 1);
  CHECK(stored[0]["title"] == "water the plants");
  CHECK(h.say("cancel the pill reminder") == Lines{"I couldn't find a reminder about pill."});
  CHECK(reminders(h).size() == 1);
  // "Don't remind me any more" is cancelling, not a reminder, and never a new one.
  CHECK(h.intent_of("don't remind me to water the plants anymore") == "schedule/cancel");
  CHECK(h.say("stop reminding me to water the plants") ==
        Lines{"OK, I cancelled the reminder to water the plants."});
  CHECK(reminders(h).empty());
}

TEST_CASE("cancel my appointment with the dentist: the appointment said any way round") {
  marvin::testing::SkillHarness h(SCHEDULE_SKILL_DIR);
  berlin(h);
  CHECK(h.say("add a dentist appointment on friday at 3 pm") ==
        Lines{"OK, I put a dentist appointment on your calendar on Friday, 9 January at 3 PM."});
  h.say("remind me to take my pills at 8 pm");
  CHECK(h.say("cancel my appointment with the dentist") ==
        Lines{"OK, I cancelled the dentist appointment."});
  const auto stored = reminders(h);
  REQUIRE(stored.size() == 1);
  CHECK(stored[0]["title"] == "take my pills");
  h.say("add my appointment with the bank to my calendar on monday at 10 am");
  CHECK(h.say("cancel my appointment with the bank") ==
        Lines{"OK, I cancelled your appointment with the bank."});
  CHECK(reminders(h).size() == 1);
}

TEST_CASE("delete all my reminders: asks first; no keeps them, yes cancels every one") {
  marvin::testing::SkillHarness h(SCHEDULE_SKILL_DIR);
  berlin(h);
  CHECK(h.say("delete all my reminders") == Lines{"You have no reminders to cancel."});
  h.say("remind me to take my pills at 8 pm");
  h.say("remind me every day at 9 to water the plants");
  h.say("set a timer for 10 minutes");
  CHECK(h.say("delete all my reminders", {"no"}) ==
        Lines{"You have 2 reminders. Should I cancel all of them?", "OK, I kept them."});
  CHECK(reminders(h).size() == 3);
  CHECK(h.say("cancel all my reminders", {"yes"}) ==
        Lines{"You have 2 reminders. Should I cancel all of them?",
              "OK, I cancelled all 2 reminders."});
  const auto stored = reminders(h);
  REQUIRE(stored.size() == 1);  // the timer is no reminder
  CHECK(stored[0]["title"] == "your timer is done");
}

TEST_CASE("when is my dentist appointment; my next appointment; the calendar said back") {
  marvin::testing::SkillHarness h(SCHEDULE_SKILL_DIR);
  berlin(h);
  CHECK(h.say("when is my next appointment") == Lines{"You have nothing on your schedule."});
  CHECK(h.say("add the dentist appointment to my calendar on friday at 3 pm") ==
        Lines{"OK, I put the dentist appointment on your calendar on Friday, 9 January at 3 PM."});
  h.say("remind me every day at 9 to take my pills");
  CHECK(h.say("when is my dentist appointment") ==
        Lines{"The dentist appointment: on Friday, 9 January at 3 PM."});
  CHECK(h.say("when do I have to take my pills") == Lines{"Take your pills: every day at 9 AM."});
  CHECK(h.say("when is my next appointment") == Lines{"Take your pills: every day at 9 AM."});
  CHECK(h.say("what time is my hair appointment") ==
        Lines{"I don't see your hair appointment on your schedule."});
  // Said back as theirs, whatever article they used (not "your the next bus").
  CHECK(h.say("when is the next bus") == Lines{"I don't see your next bus on your schedule."});
  CHECK(reminders(h).size() == 2);
}

TEST_CASE("how long until my appointment: from now, then when; days by the calendar") {
  marvin::testing::SkillHarness h(SCHEDULE_SKILL_DIR);
  berlin(h);  // Monday 10:00
  CHECK(h.intent_of("how long until my appointment") == "schedule/how_long");
  CHECK(h.intent_of("how many days till my next appointment") == "schedule/how_long");
  CHECK(h.intent_of("how soon is my doctor's appointment") == "schedule/how_long");
  CHECK(h.say("how long until my next appointment") == Lines{"You have nothing on your schedule."});
  h.say("add the dentist appointment to my calendar on friday at 3 pm");
  CHECK(h.say("how many days until my dentist appointment") ==
        Lines{"The dentist appointment: in 4 days, on Friday, 9 January at 3 PM."});
  h.say("remind me to call the bank at 11:25");
  CHECK(h.say("how long is it until my next appointment?") ==
        Lines{"Call the bank: in 1 hour and 25 minutes, today at 11:25 AM."});
  h.say("remind me every day at 9 to take my pills");
  CHECK(h.say("how long till my pills") ==
        Lines{"Take your pills: in about 23 hours, every day at 9 AM."});
  h.say("add the eye test to my calendar on the 30th of january at 9 am");
  CHECK(h.say("how long until my eye test") ==
        Lines{"The eye test: in about 4 weeks, on Friday, 30 January at 9 AM."});
  CHECK(h.say("how long until my hair appointment") ==
        Lines{"I don't see your hair appointment on your schedule."});
  CHECK(reminders(h).size() == 4);  // asking changed nothing
}

TEST_CASE("when did I last take my pills: what was marked done today") {
  marvin::testing::SkillHarness h(SCHEDULE_SKILL_DIR);
  CHECK(h.intent_of("when did I last take my pills") == "schedule/was_done");
  CHECK(h.intent_of("what time did I take my tablets") == "schedule/was_done");
}

TEST_CASE("I have a doctor's appointment on Friday at 10:30: told as news, put on the calendar") {
  marvin::testing::SkillHarness h(SCHEDULE_SKILL_DIR);
  berlin(h);
  CHECK(h.say("I have a doctor's appointment on Friday at 10:30") ==
        Lines{"OK, I put a doctor's appointment on your calendar on Friday, 9 January at 10:30 AM."});
  CHECK(h.say("I've got an appointment with the bank tomorrow at 11") ==
        Lines{"OK, I put an appointment with the bank on your calendar tomorrow at 11 AM."});
  CHECK(h.say("my daughter is coming on Saturday at noon") ==
        Lines{"OK, I put your daughter's visit on your calendar on Saturday, 10 January at 12 PM."});
  std::map<std::string, std::string> at_by_title;
  for (const json& r : reminders(h)) at_by_title[r["title"]] = r["at"];
  CHECK(at_by_title == std::map<std::string, std::string>{
                           {"doctor's appointment", "2026-01-09T10:30"},
                           {"appointment with the bank", "2026-01-06T11:00"},
                           {"my daughter's visit", "2026-01-10T12:00"}});
  CHECK(h.say("when is my doctor's appointment") ==
        Lines{"Doctor's appointment: on Friday, 9 January at 10:30 AM."});
}

TEST_CASE("I have nothing on Tuesday: the day is read back, nothing is added") {
  marvin::testing::SkillHarness h(SCHEDULE_SKILL_DIR);
  berlin(h);
  h.say("remind me on tuesday at 4 pm to call Anna");
  CHECK(h.say("I have nothing on Tuesday") ==
        Lines{"Tomorrow: call Anna at 4 PM."});
  CHECK(reminders(h).size() == 1);
}

TEST_CASE("move my dentist appointment to Thursday: same time, new day; to 11 am: same day") {
  marvin::testing::SkillHarness h(SCHEDULE_SKILL_DIR);
  berlin(h);  // Monday 5 January, 10 AM
  h.say("add the dentist appointment to my calendar on friday at 3 pm");
  CHECK(h.intent_of("move my dentist appointment to Thursday") == "schedule/move");
  CHECK(h.say("move my dentist appointment to Thursday") ==
        Lines{"OK, I moved it. The dentist appointment: on Thursday, 8 January at 3 PM."});
  auto stored = reminders(h);
  REQUIRE(stored.size() == 1);
  CHECK(stored[0]["at"] == "2026-01-08T15:00");
  CHECK(stored[0]["title"] == "the dentist appointment");
  CHECK(h.say("change my dentist appointment to 11 am") ==
        Lines{"OK, I moved it. The dentist appointment: on Thursday, 8 January at 11 AM."});
  CHECK(h.say("reschedule the dentist", {"tomorrow at 9 am"}) ==
        Lines{"When should it be instead?",
              "OK, I moved it. The dentist appointment: tomorrow at 9 AM."});
  stored = reminders(h);
  REQUIRE(stored.size() == 1);
  CHECK(stored[0]["at"] == "2026-01-06T09:00");
  // Nothing that matches: said, nothing changed.
  CHECK(h.say("move my hair appointment to friday") ==
        Lines{"I don't see your hair appointment on your schedule."});
  CHECK(reminders(h) == stored);
}

TEST_CASE("a recurring reminder moves to another time of day, not to another day") {
  marvin::testing::SkillHarness h(SCHEDULE_SKILL_DIR);
  berlin(h);
  h.say("remind me every day at 9 to take my pills");
  const auto before = reminders(h);
  CHECK(h.say("move my pill reminder to friday") ==
        Lines{"That reminder repeats every day at 9 AM. I can only move it to another time of "
              "day, for example \"move it to 10 AM\"."});
  CHECK(reminders(h) == before);
  CHECK(h.say("move my pills to 8 pm") == Lines{"OK, I moved it. Take your pills: every day at 8 PM."});
  const auto after = reminders(h);
  REQUIRE(after.size() == 1);
  CHECK(after[0]["at"] == "2026-01-05T20:00");
  CHECK(after[0]["recurrence"]["kind"] == "daily");
}

TEST_CASE("add a contact asks name and number; what is Anna's number") {
  marvin::testing::SkillHarness h(SCHEDULE_SKILL_DIR);
  CHECK(h.say("add a contact", {"Anna Schmidt", "0171 555 0101"}) ==
        Lines{"What is the contact's name?", "What is their phone number?",
              "OK, I added Anna Schmidt with the number 0 1 7 1, 5 5 5, 0 1 0 1."});
  CHECK(h.say("what is anna schmidt's number") ==
        Lines{"Anna Schmidt's number is 0 1 7 1, 5 5 5, 0 1 0 1."});
  h.robot().add_contact("Bob Meyer", {"Bob"}, {"+49 30 1234"});
  CHECK(h.say("what is Bob's number") == Lines{"Bob Meyer's number is plus 4 9, 3 0, 1 2 3 4."});
  CHECK(h.say("what is Carla's number") == Lines{"I don't have a contact called Carla."});
  // As speech comes, without the apostrophe; a name that ends in s stays as it is.
  CHECK(h.say("what is bobs number") == Lines{"Bob Meyer's number is plus 4 9, 3 0, 1 2 3 4."});
  h.robot().add_contact("James", {}, {"0301"});
  CHECK(h.say("what is james number") == Lines{"James's number is 0 3 0 1."});
  // Only an internet phone address: none to read out, but a call works.
  h.robot().add_contact_json(R"({"name": "Anna", "sip_uris": ["sip:anna@example.org"]})");
  CHECK(h.say("what is Anna's number") ==
        Lines{"I have no phone number for Anna, but I can call Anna: say \"call Anna\"."});
}

TEST_CASE("add a contact in one sentence: name and number from it, only what is missing asked") {
  marvin::testing::SkillHarness h(SCHEDULE_SKILL_DIR);
  CHECK(h.say("add Peter as a contact, his number is 0123 456") ==
        Lines{"OK, I added Peter with the number 0 1 2 3, 4 5 6."});
  CHECK(h.say("save Tom's number as 0171 234") ==
        Lines{"OK, I added Tom with the number 0 1 7 1, 2 3 4."});
  CHECK(h.say("add Mary to my contacts", {"0301 555"}) ==
        Lines{"What is their phone number?", "OK, I added Mary with the number 0 3 0 1, 5 5 5."});
  CHECK(h.say("what is Tom's number") == Lines{"Tom's number is 0 1 7 1, 2 3 4."});
  CHECK(h.say("add Sue to my contacts with the number twelve") ==
        Lines{"Sorry, \"12\" doesn't sound like a phone number. I didn't add Sue."});
  CHECK(h.say("what is Sue's number") == Lines{"I don't have a contact called Sue."});
  CHECK(h.say("add Sue to my contacts with the number banana") ==
        Lines{"Sorry, \"banana\" doesn't sound like a phone number. I didn't add Sue."});
  // Nothing between name and number: the words before the first digit are the name.
  CHECK(h.say("add a contact Mary Jones 555 1234") ==
        Lines{"OK, I added Mary Jones with the number 5 5 5, 1 2 3 4."});
  CHECK(h.say("save a new contact called Peter Smith with the number 0612 345") ==
        Lines{"OK, I added Peter Smith with the number 0 6 1 2, 3 4 5."});
  CHECK(h.say("what is Mary Jones's number") == Lines{"Mary Jones's number is 5 5 5, 1 2 3 4."});
}

TEST_CASE("delete Peter from my contacts: asked first; no, nobody or two of a name keep all") {
  marvin::testing::SkillHarness h(SCHEDULE_SKILL_DIR);
  CHECK(h.intent_of("remove anna from my address book") == "schedule/remove_contact");
  h.robot().add_contact("Peter Smith", {"Peter"}, {"0612"});
  h.robot().add_contact_json(R"({"name": "Anna Schmidt", "relation": "daughter",
                                 "phone_numbers": ["0171"]})");
  CHECK(h.say("delete Carla from my contacts") == Lines{"I don't have a contact called Carla."});
  CHECK(h.say("remove everyone from my contacts") ==
        Lines{"I remove contacts one at a time. Tell me the name of the one to remove."});
  CHECK(h.say("delete Peter from my contacts", {"no"}) ==
        Lines{"Remove Peter Smith from your contacts?", "OK, I kept Peter Smith."});
  CHECK(h.say("what is Peter's number") == Lines{"Peter Smith's number is 0 6 1 2."});
  // Two called Peter: neither is removed on a guess.
  h.robot().add_contact("Peter Brown", {"Peter"}, {"0301"});
  const Lines two = h.say("remove Peter from my address book");
  REQUIRE(two.size() == 1);
  CHECK(two[0].rfind("You have 2 contacts called Peter: Peter ", 0) == 0);
  CHECK(two[0].find("Tell me the full name of the one to remove.") != std::string::npos);
  CHECK(h.say("delete peter smith from my contacts", {"yes"}) ==
        Lines{"Remove Peter Smith from your contacts?",
              "OK, I removed Peter Smith from your contacts."});
  CHECK(h.say("what is Peter Smith's number") ==
        Lines{"I don't have a contact called Peter Smith."});
  CHECK(h.say("what is Peter's number") == Lines{"Peter Brown's number is 0 3 0 1."});
  // Who they are finds them too; the name is asked when it was not said.
  CHECK(h.say("delete a contact", {"my daughter", "yes"}) ==
        Lines{"Whose contact should I remove?", "Remove Anna Schmidt from your contacts?",
              "OK, I removed Anna Schmidt from your contacts."});
  CHECK(h.say("who are my contacts") == Lines{"You have one contact: Peter Brown."});
}

TEST_CASE("who are my contacts: none, then the names with who they are, by name") {
  marvin::testing::SkillHarness h(SCHEDULE_SKILL_DIR);
  CHECK(h.intent_of("who are my contacts") == "schedule/list_contacts");
  CHECK(h.intent_of("read me my contacts") == "schedule/list_contacts");
  CHECK(h.say("list my contacts") ==
        Lines{"You have no contacts yet. To add one, say \"add a contact\"."});
  h.robot().add_contact_json(R"({"name": "Tom Schmidt", "relation": "son"})");
  CHECK(h.say("who is in my address book") == Lines{"You have one contact: your son Tom Schmidt."});
  h.robot().add_contact_json(R"({"name": "Doctor Brown", "relation": "doctor"})");
  h.robot().add_contact_json(R"({"name": "Anna Berg"})");
  CHECK(h.say("who are my contacts") ==
        Lines{"You have 3 contacts: Anna Berg, Doctor Brown and your son Tom Schmidt."});
  for (int i = 0; i < 9; ++i) {
    h.robot().add_contact_json("{\"name\": \"Zoe " + std::string(1, static_cast<char>('A' + i)) + "\"}");
  }
  const Lines many = h.say("list my contacts");
  REQUIRE(many.size() == 1);
  CHECK(many[0].rfind("You have 12 contacts. The first ten: Anna Berg, Doctor Brown, your son "
                      "Tom Schmidt, Zoe A,", 0) == 0);
  CHECK(many[0].find("and Zoe G.") != std::string::npos);
  CHECK(many[0].find("Zoe H") == std::string::npos);
}

TEST_CASE("a number that is not one is refused and nothing is added") {
  marvin::testing::SkillHarness h(SCHEDULE_SKILL_DIR);
  const Lines said = h.say("add a contact", {"Bob", "banana"});
  REQUIRE(said.size() == 3);
  CHECK(said[2] == "Sorry, \"banana\" doesn't sound like a phone number. I didn't add Bob.");
  CHECK(h.say("what is bob's number") == Lines{"I don't have a contact called Bob."});
}

TEST_CASE("no acknowledgement when the write is refused") {
  // The built skill on a MockRobot that refuses schedule_add (no "schedule" permission):
  // the request fails and nothing "OK" is said.
  void* library = dlopen(SCHEDULE_SKILL_DIR "/skill.so", RTLD_NOW | RTLD_LOCAL);
  REQUIRE(library != nullptr);
  auto get = reinterpret_cast<marvin_skill_descriptor_fn>(dlsym(library, MARVIN_SKILL_DESCRIPTOR_SYMBOL));
  REQUIRE(static_cast<bool>(get));
  const marvin_skill_descriptor* d = get();
  marvin::testing::MockRobot robot("schedule", {});
  char error_text[512] = {};
  marvin_text_out error{error_text, sizeof error_text, 0};
  void* instance = d->create(robot.api(), robot.host(), &error);
  REQUIRE(instance != nullptr);
  const std::string slots =
      R"({"task":"take my pills","when":{"at":"2026-01-05T20:00","time_zone":"UTC",)"
      R"("recurrence":{"kind":"once"}}})";
  const marvin_request request{sizeof(marvin_request), "remind", slots.c_str(),
                               "remind me to take my pills at 8 pm"};
  CHECK(d->handle(instance, &request, &error) == MARVIN_ERR_PERMISSION);
  CHECK(std::string(error_text).find("schedule") != std::string::npos);
  CHECK(robot.said().empty());
  CHECK(robot.reminders().empty());
  d->destroy(instance);
  dlclose(library);
}

TEST_CASE("snooze: the reminder that fired fires again in ten minutes, or when asked") {
  marvin::testing::SkillHarness h(SCHEDULE_SKILL_DIR);
  berlin(h);
  h.robot().set_now(1767639600000);  // 2026-01-05T19:00Z, 8 PM in Berlin: it fired
  const std::int64_t id = h.robot().add_reminder("take my pills", "2026-01-05T20:00");
  h.robot().set_last_fired(id);
  CHECK(h.intent_of("snooze") == "schedule/snooze");
  CHECK(h.intent_of("remind me later") == "schedule/snooze");
  CHECK(h.say("snooze") == Lines{"OK, I'll remind you again at 8:10 PM."});
  auto stored = reminders(h);
  REQUIRE(stored.size() == 1);
  CHECK(stored[0]["next_fire_utc_ms"] == 1767639600000 + 10 * 60 * 1000);
  CHECK(h.say("remind me again in twenty minutes") ==
        Lines{"OK, I'll remind you again at 8:20 PM."});
  stored = reminders(h);
  REQUIRE(stored.size() == 1);
  CHECK(stored[0]["at"] == "2026-01-05T20:20");
  CHECK(h.say("remind me later") == Lines{"OK, I'll remind you again at 8:10 PM."});
}

TEST_CASE("done: the reminder that fired is marked done and does not fire again") {
  marvin::testing::SkillHarness h(SCHEDULE_SKILL_DIR);
  berlin(h);
  h.robot().set_now(1767639600000);
  const std::int64_t id = h.robot().add_reminder("take my pills", "2026-01-05T20:00");
  h.robot().set_last_fired(id);
  CHECK(h.intent_of("i took them") == "schedule/done");
  CHECK(h.intent_of("i did it") == "schedule/done");
  CHECK(h.say("I took them") == Lines{"Well done, I've marked 'take my pills' as done."});
  CHECK(reminders(h).empty());
  REQUIRE(h.robot().reminder(id).has_value());
  CHECK(json::parse(*h.robot().reminder(id))["state"] == "done");
  // Saying it again (or after the scheduler retired a fired one-off reminder) is
  // acknowledged the same way and changes nothing.
  CHECK(h.say("done") == Lines{"Well done, I've marked 'take my pills' as done."});
  CHECK(json::parse(*h.robot().reminder(id))["state"] == "done");
  // Snoozing a done one-off reminder brings it back.
  CHECK(h.say("snooze") == Lines{"OK, I'll remind you again at 8:10 PM."});
  CHECK(json::parse(*h.robot().reminder(id))["state"] == "active");
}

TEST_CASE("did I take my pills: what was marked done today, by the task's words, and when") {
  marvin::testing::SkillHarness h(SCHEDULE_SKILL_DIR);
  berlin(h);
  h.robot().set_now(1767639600000);  // 2026-01-05T19:00Z, 8 PM in Berlin: it fired
  const std::int64_t pills = h.robot().add_reminder("take my pills", "2026-01-05T20:00");
  h.robot().add_reminder("do my exercises", "2026-01-06T10:00");
  CHECK(h.intent_of("did I take my pills") == "schedule/was_done");
  CHECK(h.intent_of("have I taken my tablets today") == "schedule/was_done");
  CHECK(h.intent_of("did I forget my pills") == "schedule/was_done");
  CHECK(h.say("did I take my pills?") ==
        Lines{"You haven't told me today that you did. Your next reminder to take your pills "
              "is today at 8 PM."});
  h.robot().set_last_fired(pills);
  h.robot().set_now(1767639600000 + 5 * 60 * 1000);  // 8:05 PM
  CHECK(h.say("I took them") == Lines{"Well done, I've marked 'take my pills' as done."});
  // Any word for medicine finds the pills; "forget" turns the answer round.
  CHECK(h.say("have I taken my tablets today?") ==
        Lines{"Yes, you marked 'take my pills' as done today at 8:05 PM."});
  CHECK(h.say("did I forget my medicine?") ==
        Lines{"No, you marked 'take my pills' as done today at 8:05 PM."});
  CHECK(h.say("did I do my exercises?") ==
        Lines{"You haven't told me today that you did. Your next reminder to do your "
              "exercises is tomorrow at 10 AM."});
  CHECK(h.say("did I water the plants?") ==
        Lines{"You haven't told me today that you did. When a reminder has been done, tell me "
              "\"done\", and I'll keep track."});
  // Told again later the same evening (the one-off is done already): both times are said.
  h.robot().set_now(1767639600000 + 70 * 60 * 1000);  // 9:10 PM
  CHECK(h.say("done") == Lines{"Well done, I've marked 'take my pills' as done."});
  CHECK(h.say("did I take them?") ==
        Lines{"Yes, you marked 'take my pills' as done today at 8:05 PM and at 9:10 PM."});
  // The next day it is a new day: nothing done yet.
  h.robot().set_now(1767639600000 + 24 * 3'600'000);
  CHECK(h.say("did I take my pills") ==
        Lines{"You haven't told me today that you did. When a reminder has been done, tell me "
              "\"done\", and I'll keep track."});
  CHECK(h.say("did I take them") ==
        Lines{"You haven't marked anything as done today. When a reminder has been done, tell "
              "me \"done\", and I'll keep track."});
}

TEST_CASE("I took my pills with no reminder announced: the medicine reminder, in the log") {
  marvin::testing::SkillHarness h(SCHEDULE_SKILL_DIR);
  berlin(h);
  h.say("remind me to water the plants at 6 pm");
  h.say("remind me every day at 8 pm to take my tablets");
  CHECK(h.say("I took my pills.") == Lines{"Well done, I've marked 'take my tablets' as done."});
  const auto stored = reminders(h);
  REQUIRE(stored.size() == 2);  // a daily reminder keeps its series
  REQUIRE_FALSE(h.robot().logged_events().empty());
  CHECK(h.robot().logged_events().back().find("reminder_done: ") == 0);
  CHECK(h.robot().logged_events().back().find("'take my tablets' done") != std::string::npos);
  CHECK(h.say("have I had my medication?") ==
        Lines{"Yes, you marked 'take my tablets' as done today at 10 AM."});
  // Without a word for medicine nothing is guessed.
  CHECK(h.say("I did it") == Lines{"There is no reminder to mark as done."});
}

TEST_CASE("snooze and done with nothing fired, or with the reminder cancelled since") {
  marvin::testing::SkillHarness h(SCHEDULE_SKILL_DIR);
  berlin(h);
  h.say("remind me to take my pills at 8 pm");
  CHECK(h.say("snooze") == Lines{"There is no reminder to snooze."});
  CHECK(h.say("done") == Lines{"There is no reminder to mark as done."});
  const std::int64_t id = reminders(h).at(0)["id"].get<std::int64_t>();
  h.robot().set_last_fired(id);
  h.say("cancel the pill reminder");
  CHECK(h.say("snooze") == Lines{"There is no reminder to snooze."});
  CHECK(h.say("I did it") == Lines{"There is no reminder to mark as done."});
}

TEST_CASE("remind me in an hour, with nothing fired, is a new reminder; snooze stays a snooze") {
  marvin::testing::SkillHarness h(SCHEDULE_SKILL_DIR);
  berlin(h);
  CHECK(h.say("snooze it for 10 minutes") == Lines{"There is no reminder to snooze."});
  CHECK(h.say("remind me again in 5 minutes") == Lines{"There is no reminder to snooze."});
  CHECK(reminders(h).empty());
  CHECK(h.say("remind me in an hour", {"check the oven"}) ==
        Lines{"What should I remind you of?", "OK, I'll remind you to check the oven today at 11 AM."});
  const auto stored = reminders(h);
  REQUIRE(stored.size() == 1);
  CHECK(stored[0]["title"] == "check the oven");
  CHECK(stored[0]["at"] == "2026-01-05T11:00");
  CHECK(stored[0]["time_zone"] == "Europe/Berlin");
}

TEST_CASE("the time first, the task after \"for\", \"I have to\": the task is only the task") {
  marvin::testing::SkillHarness h(SCHEDULE_SKILL_DIR);
  berlin(h);  // Monday 10:00
  CHECK(h.say("at 5 pm remind me to take my pills") ==
        Lines{"OK, I'll remind you to take your pills today at 5 PM."});
  CHECK(h.say("set a reminder at 11 am for the doctor") ==
        Lines{"OK, I'll remind you about the doctor today at 11 AM."});
  CHECK(h.say("i have to take my pills at 9 pm") ==
        Lines{"OK, I'll remind you to take your pills today at 9 PM."});
  CHECK(h.say("i need to take my pills at 9 pm") ==
        Lines{"OK, I'll remind you to take your pills today at 9 PM."});
  std::multiset<std::string> titles;
  for (const json& r : reminders(h)) titles.insert(r["title"].get<std::string>());
  CHECK(titles ==
        std::multiset<std::string>{"take my pills", "the doctor", "take my pills", "take my pills"});
}

TEST_CASE("remind me at 5 pm, the task not said: asked for, not read from \"pm\"") {
  marvin::testing::SkillHarness h(SCHEDULE_SKILL_DIR);
  berlin(h);
  CHECK(h.say("remind me at 5 pm", {"water the plants"}) ==
        Lines{"What should I remind you of?", "OK, I'll remind you to water the plants today at 5 PM."});
  CHECK(h.say("remind me tomorrow at 9 am", {"call the bank"}) ==
        Lines{"What should I remind you of?", "OK, I'll remind you to call the bank tomorrow at 9 AM."});
}

TEST_CASE("snooze and done without the schedule permission: refused, nothing said or changed") {
  void* library = dlopen(SCHEDULE_SKILL_DIR "/skill.so", RTLD_NOW | RTLD_LOCAL);
  REQUIRE(library != nullptr);
  auto get = reinterpret_cast<marvin_skill_descriptor_fn>(dlsym(library, MARVIN_SKILL_DESCRIPTOR_SYMBOL));
  REQUIRE(static_cast<bool>(get));
  const marvin_skill_descriptor* d = get();
  marvin::testing::MockRobot robot("schedule", {});
  const std::int64_t id = robot.add_reminder("take my pills", "2026-01-05T20:00");
  robot.set_last_fired(id);
  char error_text[512] = {};
  marvin_text_out error{error_text, sizeof error_text, 0};
  void* instance = d->create(robot.api(), robot.host(), &error);
  REQUIRE(instance != nullptr);
  for (const char* intent : {"snooze", "done"}) {
    CAPTURE(intent);
    const marvin_request request{sizeof(marvin_request), intent, "{}", intent};
    CHECK(d->handle(instance, &request, &error) == MARVIN_ERR_PERMISSION);
    CHECK(std::string(error_text).find("schedule") != std::string::npos);
  }
  CHECK(robot.said().empty());
  CHECK(json::parse(*robot.reminder(id))["state"] == "active");
  CHECK(json::parse(*robot.reminder(id))["next_fire_utc_ms"] == 1767643200000);
  // The calls themselves, straight on the table.
  CHECK(robot.api()->schedule_snooze(robot.host(), id, 1767700000000) == MARVIN_ERR_PERMISSION);
  CHECK(robot.api()->schedule_done(robot.host(), id) == MARVIN_ERR_PERMISSION);
  char buffer[512] = {};
  marvin_text_out out{buffer, sizeof buffer, 0};
  CHECK(robot.api()->schedule_last_fired(robot.host(), &out) == MARVIN_ERR_PERMISSION);
  robot.set_permissions({"schedule"});
  CHECK(robot.api()->schedule_last_fired(robot.host(), &out) == MARVIN_OK);
  CHECK(json::parse(buffer)["id"] == id);
  CHECK(robot.api()->schedule_snooze(robot.host(), 999, 1767700000000) == MARVIN_ERR_NOT_FOUND);
  CHECK(robot.api()->schedule_done(robot.host(), id) == MARVIN_OK);
  CHECK(robot.api()->schedule_done(robot.host(), id) == MARVIN_OK);  // done: acknowledged again
  CHECK(robot.logged_events().size() == 2);
  CHECK(robot.api()->schedule_done(robot.host(), 999) == MARVIN_ERR_NOT_FOUND);
  const std::int64_t cancelled = robot.add_reminder("water the plants", "2026-01-05T21:00");
  CHECK(robot.api()->schedule_remove(robot.host(), cancelled) == MARVIN_OK);
  CHECK(robot.api()->schedule_done(robot.host(), cancelled) == MARVIN_ERR_NOT_FOUND);
  CHECK(robot.logged_events().size() == 2);
  d->destroy(instance);
  dlclose(library);
}

TEST_CASE("timers: set to the second, how long is left, cancel; stored like reminders") {
  marvin::testing::SkillHarness h(SCHEDULE_SKILL_DIR);
  berlin(h);
  const std::int64_t start = 1767603600000;  // the MockRobot's clock: 2026-01-05T09:00Z
  h.robot().set_now(start + 15'000);
  CHECK(h.say("set a timer for 90 seconds") == Lines{"OK, timer set for 1 minute and 30 seconds."});
  const auto stored = reminders(h);
  REQUIRE(stored.size() == 1);
  CHECK(stored[0]["title"] == "your timer is done");
  CHECK(stored[0]["next_fire_utc_ms"] == start + 105'000);  // to the second, not the minute
  h.robot().set_now(start + 45'000);
  CHECK(h.say("how long is left") == Lines{"1 minute left on your timer."});
  CHECK(h.say("what reminders do i have") == Lines{"You have no reminders set."});
  CHECK(h.say("cancel the timer") == Lines{"OK, I cancelled the timer."});
  CHECK(reminders(h).empty());
  CHECK(h.say("how long is left") == Lines{"You have no timer running."});
  CHECK(h.say("set a timer for 2 days") ==
        Lines{"Sorry, I can set a timer from one second up to 24 hours."});
  CHECK(reminders(h).empty());
}
