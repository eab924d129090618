#include <doctest/doctest.h>

#include <chrono>
#include <string>

#include <date/date.h>

#include "interpret/interpreter.h"

using namespace marvin::interpret;
using namespace date::literals;
using std::chrono::hours;
using std::chrono::minutes;

namespace {

std::int64_t utc_ms(date::sys_days day, hours h, minutes m = minutes(0)) {
  return std::chrono::duration_cast<std::chrono::milliseconds>(
             (day + h + m).time_since_epoch())
      .count();
}

// Friday 2024-03-29 10:00 in Berlin (CET, UTC+1): two days before the spring change.
Context berlin_friday() {
  Context context;
  context.now_utc_ms = utc_ms(2024_y / 3 / 29, hours(9));
  context.time_zone = "Europe/Berlin";
  return context;
}

nlohmann::json when(const std::string& text, const Context& context) {
  Interpreter interpreter;
  SlotSpec slot{"when", SlotType::kDateTime, {}};
  auto value = interpreter.parse_slot(slot, text, context);
  if (!value) return nullptr;
  return value->value;
}

}  // namespace

TEST_CASE("an hour without am/pm said late in the evening") {
  Context context;
  context.now_utc_ms = utc_ms(2024_y / 3 / 29, hours(21));  // 22:00 in Berlin
  context.time_zone = "Europe/Berlin";
  // 1..6 is the afternoon even without a day: nobody wants a reminder at 3 AM.
  CHECK(when("at 3", context)["at"] == "2024-03-30T15:00");
  CHECK(when("at half past 4", context)["at"] == "2024-03-30T16:30");
  // 7..11 is whichever comes first: the morning.
  CHECK(when("at 9", context)["at"] == "2024-03-30T09:00");
  CHECK(when("at 11", context)["at"] == "2024-03-29T23:00");
  CHECK(when("at 3 am", context)["at"] == "2024-03-30T03:00");
}

TEST_CASE("time expressions: table against Friday 2024-03-29 10:00 Europe/Berlin") {
  Context context = berlin_friday();
  struct Case {
    const char* text;
    const char* at;
    const char* kind;
  };
  const Case cases[] = {
      {"at 8 pm", "2024-03-29T20:00", "once"},
      {"at 8pm", "2024-03-29T20:00", "once"},
      {"8 p.m.", "2024-03-29T20:00", "once"},
      {"at eight", "2024-03-29T20:00", "once"},  // 08:00 has passed: the evening reading
      {"at 11", "2024-03-29T11:00", "once"},     // 11:00 is still ahead
      {"at 9", "2024-03-29T21:00", "once"},
      {"at 8 am", "2024-03-30T08:00", "once"},  // passed today: tomorrow
      {"at 20:30", "2024-03-29T20:30", "once"},
      {"at eight thirty", "2024-03-29T20:30", "once"},
      {"at half past eight in the evening", "2024-03-29T20:30", "once"},
      {"at quarter to nine", "2024-03-29T20:45", "once"},
      {"at ten past eleven", "2024-03-29T11:10", "once"},
      {"at 20 minutes to 12", "2024-03-29T11:40", "once"},
      {"at 8 o'clock", "2024-03-29T20:00", "once"},
      {"at eight oh five", "2024-03-29T20:05", "once"},
      {"at noon", "2024-03-29T12:00", "once"},
      {"at midnight", "2024-03-30T00:00", "once"},
      {"at 11 at night", "2024-03-29T23:00", "once"},
      {"in 20 minutes", "2024-03-29T10:20", "once"},
      {"in an hour and a half", "2024-03-29T11:30", "once"},
      {"in 2 days", "2024-03-31T09:00", "once"},  // days: the day, at its usual hour
      {"in a week", "2024-04-05T09:00", "once"},
      {"in 48 hours", "2024-03-31T11:00", "once"},  // on the clock (summer time began)
      {"tomorrow at nine", "2024-03-30T09:00", "once"},
      {"tomorrow at 3", "2024-03-30T15:00", "once"},  // 1..6 with a day: afternoon
      {"at 9 tomorrow", "2024-03-30T09:00", "once"},
      {"tomorrow", "2024-03-30T09:00", "once"},
      {"the day after tomorrow at 7 30 am", "2024-03-31T07:30", "once"},
      {"today at 5 pm", "2024-03-29T17:00", "once"},
      {"tonight at 8", "2024-03-29T20:00", "once"},
      {"on monday at 10", "2024-04-01T10:00", "once"},
      {"at 10 on monday", "2024-04-01T10:00", "once"},
      {"every day at 8", "2024-03-30T08:00", "daily"},
      {"daily at 8 pm", "2024-03-29T20:00", "daily"},
      {"every weekday at 7:30", "2024-04-01T07:30", "weekdays"},
      {"on weekdays at 7:30", "2024-04-01T07:30", "weekdays"},
      {"every monday at 10", "2024-04-01T10:00", "weekly"},
      {"on mondays at 10", "2024-04-01T10:00", "weekly"},
      {"every tuesday and thursday at 6 pm", "2024-04-02T18:00", "weekly"},
      {"every weekend at 9", "2024-03-30T09:00", "weekly"},
      {"every 2 hours", "2024-03-29T12:00", "interval"},
      {"every hour", "2024-03-29T11:00", "interval"},
      // A part of the day: the half of the clock for an hour without am/pm, or its hour.
      {"tomorrow morning at 6", "2024-03-30T06:00", "once"},  // not 18:00 as "tomorrow at 6"
      {"at 6 tomorrow morning", "2024-03-30T06:00", "once"},
      {"tomorrow morning", "2024-03-30T09:00", "once"},
      {"tomorrow afternoon", "2024-03-30T15:00", "once"},
      {"tonight", "2024-03-29T20:00", "once"},  // a reminder "tonight" is not at 9 AM
      {"this evening", "2024-03-29T19:00", "once"},
      {"this evening at 7", "2024-03-29T19:00", "once"},
      {"on monday evening at 7", "2024-04-01T19:00", "once"},
      {"monday morning", "2024-04-01T09:00", "once"},
      {"tomorrow at night", "2024-03-30T21:00", "once"},
      {"at 8 in the morning", "2024-03-30T08:00", "once"},
      {"every morning at 7", "2024-03-30T07:00", "daily"},
      {"every morning", "2024-03-30T09:00", "daily"},
      {"every evening", "2024-03-29T19:00", "daily"},
      // Meals and bed (Friday 10:00): the usual hour, one earlier "before", one later "after".
      {"after lunch", "2024-03-29T13:00", "once"},
      {"at half seven tomorrow", "2024-03-30T07:30", "once"},
      {"half past seven tomorrow", "2024-03-30T07:30", "once"},
      {"at lunchtime", "2024-03-29T12:00", "once"},
      {"before breakfast", "2024-03-30T07:00", "once"},
      {"every day with breakfast", "2024-03-30T08:00", "daily"},
      {"tomorrow after dinner", "2024-03-30T19:00", "once"},
      {"before supper", "2024-03-29T17:00", "once"},
      {"at bedtime", "2024-03-29T21:00", "once"},
      {"before going to bed", "2024-03-29T21:00", "once"},
      {"every day before bed", "2024-03-29T21:00", "daily"},
      {"every night at 10", "2024-03-29T22:00", "daily"},
      {"every day in the evening", "2024-03-29T19:00", "daily"},
      // Holidays on fixed dates: the next one (Christmas 2024; New Year's Day 2025).
      {"christmas", "2024-12-25T09:00", "once"},
      {"on christmas day at 6 pm", "2024-12-25T18:00", "once"},
      {"christmas eve", "2024-12-24T09:00", "once"},
      {"boxing day", "2024-12-26T09:00", "once"},
      {"new year's eve", "2024-12-31T09:00", "once"},
      {"new year's day", "2025-01-01T09:00", "once"},
      {"new year", "2025-01-01T09:00", "once"},
      {"on halloween", "2024-10-31T09:00", "once"},
      {"valentine's day", "2025-02-14T09:00", "once"},
      // Feasts that move with Easter (Sunday 2024-03-31; 2025-04-20): the next one.
      {"easter", "2024-03-31T09:00", "once"},
      {"on easter sunday at 3 pm", "2024-03-31T15:00", "once"},
      {"easter monday", "2024-04-01T09:00", "once"},
      {"good friday", "2024-03-29T10:00", "once"},  // today (without a time: now)
      {"whit monday", "2024-05-20T09:00", "once"},
      {"ascension day", "2024-05-09T09:00", "once"},
      {"easter 2027", "2027-03-28T09:00", "once"},
      {"christmas this year", "2024-12-25T09:00", "once"},
  };
  for (const Case& c : cases) {
    CAPTURE(c.text);
    nlohmann::json value = when(c.text, context);
    REQUIRE(value.is_object());
    CHECK(value["at"] == c.at);
    CHECK(value["recurrence"]["kind"] == c.kind);
    CHECK(value["time_zone"] == "Europe/Berlin");
  }
  // "next friday" on a Friday morning after 9: a week later (today's 09:00 has passed).
  CHECK(when("next friday at 9", context)["at"] == "2024-04-05T09:00");
  // Friday at 11 on a Friday at 10: today.
  CHECK(when("on friday at 11", context)["at"] == "2024-03-29T11:00");
}

TEST_CASE("time expressions: recurrence objects and instants") {
  Context context = berlin_friday();
  nlohmann::json daily = when("every day at 8", context);
  CHECK(daily["recurrence"] == nlohmann::json{{"kind", "daily"}, {"time", "08:00"}});
  CHECK(daily["utc_ms"] == utc_ms(2024_y / 3 / 30, hours(7)));
  CHECK(daily["time_given"] == true);

  nlohmann::json weekdays = when("every weekday at 7:30", context);
  CHECK(weekdays["recurrence"] ==
        nlohmann::json{{"kind", "weekdays"},
                       {"weekdays", {"monday", "tuesday", "wednesday", "thursday", "friday"}},
                       {"time", "07:30"}});
  nlohmann::json weekly = when("every sunday and tuesday at 6 pm", context);
  CHECK(weekly["recurrence"]["weekdays"] == nlohmann::json{"tuesday", "sunday"});
  CHECK(weekly["at"] == "2024-03-31T18:00");

  nlohmann::json interval = when("every 30 minutes", context);
  CHECK(interval["recurrence"] ==
        nlohmann::json{{"kind", "interval"}, {"every_seconds", 1800}});
  CHECK(interval["utc_ms"] == context.now_utc_ms + 1800 * 1000);

  nlohmann::json relative = when("in 20 minutes", context);
  CHECK(relative["utc_ms"] == context.now_utc_ms + 1200 * 1000);

  nlohmann::json no_time = when("on monday", context);
  CHECK(no_time["time_given"] == false);
  CHECK(no_time["at"] == "2024-04-01T09:00");

  // Whether a day was said, or only a time of day ("move it to 3 pm": its own day).
  CHECK(when("at 3 pm", context)["day_given"] == false);
  CHECK(when("half past seven", context)["day_given"] == false);
  CHECK(when("on monday", context)["day_given"] == true);
  CHECK(when("tomorrow at 3 pm", context)["day_given"] == true);
  CHECK(when("today at 11 pm", context)["day_given"] == true);
  CHECK(when("on april 3rd at 7:30", context)["day_given"] == true);
  CHECK(when("every day at 8", context)["day_given"] == true);
  CHECK(when("in 20 minutes", context)["day_given"] == true);
}

TEST_CASE("time expressions: two times of one day or recurrence, joined by and") {
  Context context = berlin_friday();  // 10:00
  struct Case {
    const char* text;
    const char* at;
    const char* also;
    const char* kind;
  };
  const Case cases[] = {
      {"every day at 9 am and 9 pm", "2024-03-30T09:00", "2024-03-29T21:00", "daily"},
      {"every morning and evening", "2024-03-30T09:00", "2024-03-29T19:00", "daily"},
      {"tomorrow at 8 and at 6", "2024-03-30T08:00", "2024-03-30T18:00", "once"},
      {"at 8 and 6 on monday", "2024-04-01T08:00", "2024-04-01T18:00", "once"},
      // The bare hour is the other half of the day: not 20:00 twice.
      {"at 8 and at 8 pm", "2024-03-30T08:00", "2024-03-29T20:00", "once"},
      {"at 11 am and 11", "2024-03-29T11:00", "2024-03-29T23:00", "once"},
      {"every monday at 9 and 5 pm", "2024-04-01T09:00", "2024-04-01T17:00", "weekly"},
  };
  for (const Case& c : cases) {
    CAPTURE(c.text);
    nlohmann::json value = when(c.text, context);
    REQUIRE(value.is_object());
    CHECK(value["at"] == c.at);
    CHECK(value["recurrence"]["kind"] == c.kind);
    REQUIRE(value["also"].size() == 1);
    CHECK(value["also"][0]["at"] == c.also);
    CHECK(value["also"][0]["recurrence"]["kind"] == c.kind);
  }
  // One phrase with "and" inside stays one: no "also".
  CHECK_FALSE(when("every tuesday and thursday at 6 pm", context).contains("also"));
  // Not a pair: two days, a duration, an interval, a week, the same time twice, half of one.
  for (const char* text : {"monday at 9 and tuesday at 10", "in 20 minutes and at 5",
                           "every 2 hours and at 8", "next week and at 8", "at 8 pm and 8 pm",
                           "at 8 and", "and at 8", "tomorrow and at 8 and at 9"}) {
    CAPTURE(text);
    CHECK(when(text, context).is_null());
  }
}

TEST_CASE("time expressions: spring forward in Europe/Berlin (2024-03-31)") {
  Context context;
  context.time_zone = "Europe/Berlin";
  context.now_utc_ms = utc_ms(2024_y / 3 / 30, hours(9));  // Saturday 10:00 CET

  // 02:30 does not exist on Sunday: the reminder fires at the transition, 03:00 CEST.
  nlohmann::json gap = when("tomorrow at 2:30 am", context);
  CHECK(gap["at"] == "2024-03-31T03:00");
  CHECK(gap["utc_ms"] == utc_ms(2024_y / 3 / 31, hours(1)));

  // "tomorrow at 10" is only 23 hours away; "in 24 hours" lands at 11:00 local.
  CHECK(when("tomorrow at 10", context)["utc_ms"] == utc_ms(2024_y / 3 / 31, hours(8)));
  CHECK(when("in 24 hours", context)["at"] == "2024-03-31T11:00");
  // A daily time keeps its wall-clock hour across the change.
  nlohmann::json daily = when("every day at 8", context);
  CHECK(daily["at"] == "2024-03-31T08:00");
  CHECK(daily["utc_ms"] == utc_ms(2024_y / 3 / 31, hours(6)));
}

TEST_CASE("time expressions: fall back in Europe/Berlin (2024-10-27)") {
  Context context;
  context.time_zone = "Europe/Berlin";
  context.now_utc_ms = utc_ms(2024_y / 10 / 26, hours(10));  // Saturday 12:00 CEST

  // 02:30 happens twice: the first one (CEST, 00:30 UTC).
  nlohmann::json twice = when("tomorrow at 2:30 am", context);
  CHECK(twice["at"] == "2024-10-27T02:30");
  CHECK(twice["utc_ms"] == utc_ms(2024_y / 10 / 27, hours(0), minutes(30)));
  // "tomorrow at 10" is 25 hours away (CET, 09:00 UTC).
  CHECK(when("tomorrow at 10", context)["utc_ms"] == utc_ms(2024_y / 10 / 27, hours(9)));
}

TEST_CASE("time expressions: other zones and UTC") {
  Context context;  // UTC by default
  context.now_utc_ms = utc_ms(2024_y / 7 / 1, hours(23), minutes(50));  // Monday
  CHECK(when("in 20 minutes", context)["at"] == "2024-07-02T00:10");
  CHECK(when("at 8", context)["at"] == "2024-07-02T08:00");

  context.time_zone = "America/New_York";  // 19:50 EDT
  CHECK(when("at 8", context)["at"] == "2024-07-01T20:00");
  CHECK(when("tomorrow at 8", context)["at"] == "2024-07-02T08:00");
}

TEST_CASE("time expressions: day ranges (weeks run Monday to Sunday)") {
  Context context = berlin_friday();
  struct Case {
    const char* text;
    const char* at;
    int days;
  };
  const Case cases[] = {
      {"next week", "2024-04-01T09:00", 7},
      {"for next week", "2024-04-01T09:00", 7},
      {"this week", "2024-03-29T10:00", 3},  // 09:00 today has passed: from now to Sunday
      {"this weekend", "2024-03-30T09:00", 2},
      {"over the weekend", "2024-03-30T09:00", 2},
      {"next weekend", "2024-04-06T09:00", 2},
  };
  for (const Case& c : cases) {
    CAPTURE(c.text);
    auto value = when(c.text, context);
    REQUIRE(value.is_object());
    CHECK(value["at"] == c.at);
    CHECK(value["days"] == c.days);
    CHECK(value["time_given"] == false);
  }
  CHECK_FALSE(when("tomorrow", context).contains("days"));
  // Saturday: "this weekend" is today and tomorrow; Sunday: just today.
  context.now_utc_ms = utc_ms(2024_y / 3 / 30, hours(6));  // 07:00 local
  CHECK(when("this weekend", context)["at"] == "2024-03-30T09:00");
  CHECK(when("this weekend", context)["days"] == 2);
  context.now_utc_ms = utc_ms(2024_y / 3 / 31, hours(5));  // 07:00 local (CEST)
  CHECK(when("this weekend", context)["days"] == 1);
  CHECK(when("next week", context)["at"] == "2024-04-01T09:00");
  // Sunday: "this week" is today and the coming week, not today alone.
  CHECK(when("this week", context)["at"] == "2024-03-31T09:00");
  CHECK(when("this week", context)["days"] == 8);
}

TEST_CASE("time expressions: \"wake me\" and \"alarm\" read an hour without am/pm as morning") {
  const Context context = berlin_friday();  // Friday 10:00
  Interpreter interpreter;
  const SlotSpec slot{"when", SlotType::kDateTime, {}};
  auto at = [&](const char* answer, const char* request) {
    auto value = interpreter.parse_slot(slot, answer, context, request);
    return value ? value->value.at("at").get<std::string>() : std::string("(none)");
  };
  CHECK(at("tomorrow at 6", "") == "2024-03-30T18:00");
  CHECK(at("tomorrow at 6", "set an alarm") == "2024-03-30T06:00");
  CHECK(at("6", "wake me up") == "2024-03-30T06:00");  // today's 06:00 has passed
  CHECK(at("every day at 6", "Wake me, please") == "2024-03-30T06:00");
  CHECK(at("at 6 pm", "set an alarm") == "2024-03-29T18:00");       // said: pm
  CHECK(at("tonight at 9", "set an alarm") == "2024-03-29T21:00");  // said: tonight
  CHECK(at("tomorrow at 6", "remind me to wake the kids") == "2024-03-30T06:00");
  CHECK(at("tomorrow at 6", "remind me to call the bank") == "2024-03-30T18:00");
}

TEST_CASE("time expressions: not times") {
  Context context = berlin_friday();
  const char* cases[] = {"",         "at",          "at 25",           "at 13 pm",
                         "tomorrow tomorrow",       "every",           "in",
                         "in 20",    "at 8 at 9",   "today at 8 am",   "eight apples",
                         "at 7:75",  "every 2 hours at 8",             "in 20 minutes tomorrow",
                         "on",       "every 10 seconds",          "next week at 8",
                         "the week after"};
  for (const char* text : cases) {
    CAPTURE(text);
    CHECK(when(text, context).is_null());
  }
  // Parts of the day: one at most, one day at most, never with a week or an interval.
  // "my bed" is the furniture, not bedtime ("how far is my bed").
  for (const char* text : {"after bed", "after lunch after dinner", "with", "before the",
                           "my bed", "before my bed",
                           "morning morning", "this evening tomorrow", "tonight in the morning",
                           "next week in the morning", "every 2 hours in the evening"}) {
    CAPTURE(text);
    CHECK(when(text, context).is_null());
  }
  // Holidays: not half a name, not two days.
  for (const char* text : {"good", "whit", "valentine's", "boxing", "new", "christmas tomorrow",
                           "christmas on monday", "halloween eve", "easter tomorrow"}) {
    CAPTURE(text);
    CHECK(when(text, context).is_null());
  }
}

TEST_CASE("time expressions: unknown time zone is reported") {
  Context context = berlin_friday();
  context.time_zone = "Mars/Olympus";
  Interpreter interpreter;
  CHECK_THROWS_WITH(interpreter.parse_slot({"when", SlotType::kDateTime, {}}, "at 8", context),
                    doctest::Contains("unknown time zone \"Mars/Olympus\""));
}

TEST_CASE("calendar dates with month names, against Friday 2024-03-29 10:00 Europe/Berlin") {
  Context context = berlin_friday();
  struct Case {
    const char* text;
    const char* at;  // nullptr: not a time
  };
  const Case cases[] = {
      {"on march 31st", "2024-03-31T09:00"},  // across the spring change (CEST): still 09:00
      {"april 2", "2024-04-02T09:00"},
      {"on the 3rd of april at 5 pm", "2024-04-03T17:00"},
      {"at 5 pm on the 3rd of april", "2024-04-03T17:00"},
      {"3 april", "2024-04-03T09:00"},           // a day number, not the hour 3
      {"april the 3rd", "2024-04-03T09:00"},
      {"the fourth of july", "2024-07-04T09:00"},  // "fourth" normalises to "4th"
      {"the twenty first of may", "2024-05-21T09:00"},  // "20 1st"
      {"sept 21st", "2024-09-21T09:00"},
      {"on feb 2", "2025-02-02T09:00"},    // passed this year: next year
      {"on march 29", "2024-03-29T10:00"},  // today, no time said: now
      {"march 29 at 8 am", "2025-03-29T08:00"},  // today's 8 am has passed
      {"february 29", "2028-02-29T09:00"},  // the next leap day
      {"march 4th 2027", "2027-03-04T09:00"},
      {"march 4th 2019", nullptr},  // past: the slot is always a time ahead
      {"february 30", nullptr},
      {"march 32nd", nullptr},
      {"may", nullptr},  // a month needs its day ("may i ...")
      {"march", nullptr},
  };
  for (const Case& c : cases) {
    CAPTURE(c.text);
    nlohmann::json value = when(c.text, context);
    if (c.at == nullptr) {
      CHECK(value.is_null());
      continue;
    }
    REQUIRE(value.is_object());
    CHECK(value["at"] == c.at);
    CHECK(value["recurrence"]["kind"] == "once");
  }
  // A time said with the date is marked as said; without it, 09:00 is assumed.
  CHECK(when("on april 3rd at 7:30", context)["time_given"] == true);
  CHECK(when("on april 3rd", context)["time_given"] == false);
}
