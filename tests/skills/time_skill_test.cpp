// The built-in time skill, loaded from the build tree, with a fixed clock and time zone.
#include <doctest/doctest.h>

#include <marvin/testing/skill_harness.hpp>

using Lines = std::vector<std::string>;

namespace {

// 2026-11-21T14:05:00Z, a Saturday.
constexpr std::int64_t kSaturdayAfternoonUtc = 1795269900000;

}  // namespace

TEST_CASE("what time is it: the host's clock in the owner's time zone") {
  marvin::testing::SkillHarness harness(TIME_SKILL_DIR);
  harness.robot().set_now(kSaturdayAfternoonUtc);
  harness.robot().set_time_zone("Europe/Berlin");
  CHECK(harness.say("What time is it?") == Lines{"It's 3:05 PM."});
  harness.robot().set_time_zone("America/New_York");
  CHECK(harness.say("tell me the time") == Lines{"It's 9:05 AM."});
  harness.robot().set_time_zone("UTC");
  CHECK(harness.say("what time is it now") == Lines{"It's 2:05 PM."});
}

TEST_CASE("what day is it: the local date, which may differ from UTC's") {
  marvin::testing::SkillHarness harness(TIME_SKILL_DIR);
  harness.robot().set_now(kSaturdayAfternoonUtc);
  harness.robot().set_time_zone("Europe/Berlin");
  CHECK(harness.say("what day is it today") == Lines{"Today is Saturday, 21 November 2026."});
  harness.robot().set_time_zone("Pacific/Kiritimati");  // UTC+14: already Sunday
  CHECK(harness.say("what is the date") == Lines{"Today is Sunday, 22 November 2026."});
}

TEST_CASE("the date of another day: tomorrow, a weekday") {
  marvin::testing::SkillHarness harness(TIME_SKILL_DIR);
  harness.robot().set_now(kSaturdayAfternoonUtc);
  harness.robot().set_time_zone("Europe/Berlin");
  CHECK(harness.say("what's the date tomorrow") == Lines{"Tomorrow is Sunday, 22 November 2026."});
  CHECK(harness.say("what date is next friday") == Lines{"That is Friday, 27 November 2026."});
  CHECK(harness.say("what is the date today") == Lines{"Today is Saturday, 21 November 2026."});
}

TEST_CASE("is it Sunday, is it the weekend: yes or no, then the date; the year and month") {
  marvin::testing::SkillHarness harness(TIME_SKILL_DIR);
  harness.robot().set_now(kSaturdayAfternoonUtc);
  harness.robot().set_time_zone("Europe/Berlin");
  CHECK(harness.say("is it the weekend?") == Lines{"Yes, today is Saturday, 21 November 2026."});
  CHECK(harness.say("is today Sunday") == Lines{"No, today is Saturday, 21 November 2026."});
  CHECK(harness.say("is it Saturday today") == Lines{"Yes, today is Saturday, 21 November 2026."});
  CHECK(harness.say("is it a weekday") == Lines{"No, today is Saturday, 21 November 2026."});
  CHECK(harness.say("what year is it") == Lines{"It's 2026."});
  CHECK(harness.say("which month is it now") == Lines{"It's November 2026."});
  harness.robot().set_time_zone("Pacific/Kiritimati");  // UTC+14: already Sunday
  CHECK(harness.say("is it Sunday") == Lines{"Yes, today is Sunday, 22 November 2026."});
}

TEST_CASE("is it morning or evening: the part of the day, then the clock") {
  marvin::testing::SkillHarness harness(TIME_SKILL_DIR);
  harness.robot().set_now(kSaturdayAfternoonUtc);
  harness.robot().set_time_zone("Europe/Berlin");
  CHECK(harness.say("is it morning or afternoon") == Lines{"It's the afternoon: 3:05 PM."});
  harness.robot().set_time_zone("America/New_York");
  CHECK(harness.say("is it still morning") == Lines{"It's the morning: 9:05 AM."});
  harness.robot().set_time_zone("Pacific/Kiritimati");  // 4:05 AM
  CHECK(harness.say("is it day or night") == Lines{"It's night: 4:05 AM."});
  harness.robot().set_time_zone("Asia/Kolkata");  // 7:35 PM
  CHECK(harness.say("what part of the day is it") == Lines{"It's the evening: 7:35 PM."});
  CHECK(harness.say("what time is it") == Lines{"It's 7:35 PM."});
}

TEST_CASE("midnight and noon read as 12") {
  marvin::testing::SkillHarness harness(TIME_SKILL_DIR);
  harness.robot().set_time_zone("UTC");
  harness.robot().set_now(1795219200000);  // 2026-11-21T00:00Z
  CHECK(harness.say("what time is it") == Lines{"It's 12:00 AM."});
  harness.robot().set_now(1795219200000 + 12 * 3600 * 1000 + 9 * 60 * 1000);
  CHECK(harness.say("what time is it") == Lines{"It's 12:09 PM."});
}

TEST_CASE("an unknown time zone falls back to UTC instead of failing") {
  marvin::testing::SkillHarness harness(TIME_SKILL_DIR);
  harness.robot().set_now(kSaturdayAfternoonUtc);
  harness.robot().set_time_zone("Mars/Olympus_Mons");
  CHECK(harness.say("what time is it") == Lines{"It's 2:05 PM."});
}

TEST_CASE("the time in a city the tz database names; the local time when it names none") {
  marvin::testing::SkillHarness harness(TIME_SKILL_DIR);
  harness.robot().set_now(kSaturdayAfternoonUtc);  // 14:05 UTC
  harness.robot().set_time_zone("Europe/Berlin");
  CHECK(harness.say("what time is it in tokyo") == Lines{"In Tokyo it's 11:05 PM."});
  CHECK(harness.say("what's the time in New York?") == Lines{"In New York it's 9:05 AM."});
  CHECK(harness.say("could you tell me the current time in london") ==
        Lines{"In London it's 2:05 PM."});
  CHECK(harness.say("what time is it in mexico") == Lines{"In Mexico City it's 8:05 AM."});
  CHECK(harness.say("what's the time in new york right now") == Lines{"In New York it's 9:05 AM."});
  CHECK(harness.say("what time is it in atlantis") ==
        Lines{"I don't know the time zone of Atlantis. Here it's 3:05 PM."});
  CHECK(harness.say("what time is it") == Lines{"It's 3:05 PM."});  // no place: here
}

TEST_CASE("how many days until christmas; how long until an hour; today and tomorrow") {
  marvin::testing::SkillHarness harness(TIME_SKILL_DIR);
  harness.robot().set_now(kSaturdayAfternoonUtc);  // 3:05 PM in Berlin
  harness.robot().set_time_zone("Europe/Berlin");
  CHECK(harness.say("how many days until christmas") ==
        Lines{"It's 34 days until Friday, 25 December."});
  CHECK(harness.say("how long is it till new year's day") ==
        Lines{"It's 41 days until Friday, 1 January 2027."});
  CHECK(harness.say("when is christmas eve") == Lines{"It's 33 days until Thursday, 24 December."});
  // Easter moves: its date is reckoned for the year (Sunday 28 March 2027).
  CHECK(harness.say("when is easter") == Lines{"It's 127 days until Sunday, 28 March 2027."});
  CHECK(harness.say("what day is good friday") == Lines{"That is Friday, 26 March 2027."});
  CHECK(harness.say("what day of the week is christmas this year") ==
        Lines{"That is Friday, 25 December 2026."});
  CHECK(harness.say("how many days until sunday") == Lines{"That's tomorrow, Sunday, 22 November."});
  CHECK(harness.say("how long until 5 pm") == Lines{"It's 1 hour and 55 minutes until 5 PM."});
  CHECK(harness.say("how many hours until midnight") ==
        Lines{"It's 8 hours and 55 minutes until midnight."});
  CHECK(harness.say("how long until 9 am") == Lines{"It's 17 hours and 55 minutes until 9 AM tomorrow."});
  // In UTC+14 it is already Sunday: Christmas is a day nearer.
  harness.robot().set_time_zone("Pacific/Kiritimati");
  CHECK(harness.say("how many days till christmas") == Lines{"It's 33 days until Friday, 25 December."});
}

TEST_CASE("what time will it be in two hours: the clock then, and whether that is tomorrow") {
  marvin::testing::SkillHarness harness(TIME_SKILL_DIR);
  harness.robot().set_now(kSaturdayAfternoonUtc);  // 3:05 PM in Berlin
  harness.robot().set_time_zone("Europe/Berlin");
  CHECK(harness.say("what time will it be in two hours") ==
        Lines{"In 2 hours it will be 5:05 PM."});
  CHECK(harness.say("what time is it in 20 minutes") == Lines{"In 20 minutes it will be 3:25 PM."});
  CHECK(harness.say("what will the time be 10 hours from now") ==
        Lines{"In 10 hours it will be 1:05 AM tomorrow."});
  // A place is still a place, though it follows "in" as well.
  CHECK(harness.say("what time is it in tokyo") == Lines{"In Tokyo it's 11:05 PM."});
}
