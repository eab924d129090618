// Recurrence arithmetic in fixed time zones, across daylight-saving changes.
#include <doctest/doctest.h>

#include <vector>

#include "data/recurrence.h"
#include "test_support.h"

using namespace marvin::data;

namespace {

using marvin::data::test::kMinute;
constexpr std::int64_t kHour = 60 * kMinute;

Reminder make(const char* local_first, const char* zone, Recurrence rec = {}) {
  Reminder r;
  r.title = "take my pills";
  r.time_zone = zone;
  r.first_fire_utc_ms = local_to_utc_ms(local_first, zone);
  r.recurrence = rec;
  return r;
}

// The next `n` occurrences after `after`, as local "YYYY-MM-DD HH:MM" plus the UTC offset
// check done by the caller through utc values.
std::vector<std::string> next_n(const Reminder& r, std::int64_t after, int n) {
  std::vector<std::string> out;
  for (int i = 0; i < n; ++i) {
    auto next = next_occurrence(r, after);
    if (!next) break;
    out.push_back(format_local(*next, r.time_zone));
    after = *next;
  }
  return out;
}

Recurrence kind(Recurrence::Kind k) {
  Recurrence r;
  r.kind = k;
  return r;
}

}  // namespace

TEST_CASE("local times convert to UTC with the zone's offset") {
  // Berlin is UTC+1 in winter, UTC+2 in summer.
  CHECK(local_to_utc_ms("2026-01-15T08:00", "Europe/Berlin") ==
        local_to_utc_ms("2026-01-15T07:00", "UTC"));
  CHECK(local_to_utc_ms("2026-07-15T08:00", "Europe/Berlin") ==
        local_to_utc_ms("2026-07-15T06:00", "UTC"));
  CHECK(local_to_utc_ms("2026-07-15 08:00:30", "America/New_York") ==
        local_to_utc_ms("2026-07-15T12:00:30", "UTC"));
  CHECK_THROWS_WITH(local_to_utc_ms("2026-02-30T08:00", "UTC"),
                    "time '2026-02-30T08:00': expected local time YYYY-MM-DDTHH:MM");
  CHECK_THROWS_WITH(local_to_utc_ms("2026-02-03T08:00x", "UTC"),
                    "time '2026-02-03T08:00x': expected local time YYYY-MM-DDTHH:MM");
  CHECK_THROWS_WITH(local_to_utc_ms("2026-02-03T08:00", "Mars/Olympus"),
                    "time_zone: unknown IANA time zone 'Mars/Olympus'");
}

TEST_CASE("a one-off reminder fires once") {
  const Reminder r = make("2026-05-01T20:00", "Europe/Berlin");
  CHECK(next_occurrence(r, r.first_fire_utc_ms - 1) == r.first_fire_utc_ms);
  CHECK_FALSE(next_occurrence(r, r.first_fire_utc_ms).has_value());
  CHECK_FALSE(last_occurrence_at_or_before(r, r.first_fire_utc_ms - 1).has_value());
  CHECK(last_occurrence_at_or_before(r, r.first_fire_utc_ms + kHour) == r.first_fire_utc_ms);
}

TEST_CASE("daily keeps the local time across the spring change in Berlin") {
  // DST starts 2026-03-29 02:00 -> 03:00 in Berlin.
  const Reminder r = make("2026-03-27T08:00", "Europe/Berlin", kind(Recurrence::Kind::kDaily));
  const auto times = next_n(r, r.first_fire_utc_ms - 1, 4);
  CHECK(times == std::vector<std::string>{"2026-03-27 08:00", "2026-03-28 08:00",
                                          "2026-03-29 08:00", "2026-03-30 08:00"});
  // 23 real hours between the 28th and the 29th.
  const auto d28 = *next_occurrence(r, r.first_fire_utc_ms);
  CHECK(*next_occurrence(r, d28) - d28 == 23 * kHour);
}

TEST_CASE("a daily time inside the spring gap fires at the first valid minute after it") {
  const Reminder r = make("2026-03-27T02:30", "Europe/Berlin", kind(Recurrence::Kind::kDaily));
  const auto times = next_n(r, r.first_fire_utc_ms - 1, 4);
  CHECK(times == std::vector<std::string>{"2026-03-27 02:30", "2026-03-28 02:30",
                                          "2026-03-29 03:00", "2026-03-30 02:30"});
  // 03:00 CEST on the 29th is 01:00 UTC.
  const auto gap_day = local_to_utc_ms("2026-03-29T01:00", "UTC");
  CHECK(next_occurrence(r, gap_day - 1) == gap_day);
}

TEST_CASE("an ambiguous time in the autumn fold fires once, at its first occurrence") {
  // Berlin: 2026-10-25 03:00 CEST -> 02:00 CET, so 02:30 happens twice.
  const Reminder r = make("2026-10-23T02:30", "Europe/Berlin", kind(Recurrence::Kind::kDaily));
  const auto fold_first = local_to_utc_ms("2026-10-25T00:30", "UTC");  // 02:30 CEST
  const auto fold_second = fold_first + kHour;                         // 02:30 CET
  const auto next_day = local_to_utc_ms("2026-10-26T01:30", "UTC");    // 02:30 CET
  CHECK(next_occurrence(r, fold_first - 1) == fold_first);
  CHECK(next_occurrence(r, fold_first) == next_day);
  CHECK(next_occurrence(r, fold_second - 1) == next_day);
}

TEST_CASE("New York: daily across both changes") {
  // 2026-03-08 02:00 -> 03:00 and 2026-11-01 02:00 -> 01:00.
  const Reminder r = make("2026-03-07T09:00", "America/New_York", kind(Recurrence::Kind::kDaily));
  const auto mar7 = r.first_fire_utc_ms;
  const auto mar8 = *next_occurrence(r, mar7);
  CHECK(mar7 == local_to_utc_ms("2026-03-07T14:00", "UTC"));  // EST, UTC-5
  CHECK(mar8 == local_to_utc_ms("2026-03-08T13:00", "UTC"));  // EDT, UTC-4
  const Reminder fold = make("2026-10-31T01:30", "America/New_York", kind(Recurrence::Kind::kDaily));
  const auto nov1 = *next_occurrence(fold, fold.first_fire_utc_ms);
  CHECK(nov1 == local_to_utc_ms("2026-11-01T05:30", "UTC"));  // 01:30 EDT, the first one
  CHECK(format_local(*next_occurrence(fold, nov1), "America/New_York") == "2026-11-02 01:30");
}

TEST_CASE("weekdays and weekly days") {
  // 2026-11-20 is a Friday.
  const Reminder wd = make("2026-11-20T07:15", "Europe/Berlin", kind(Recurrence::Kind::kWeekdays));
  CHECK(next_n(wd, wd.first_fire_utc_ms - 1, 3) ==
        std::vector<std::string>{"2026-11-20 07:15", "2026-11-23 07:15", "2026-11-24 07:15"});
  Recurrence weekly = kind(Recurrence::Kind::kWeekly);
  weekly.weekdays = 0b1000101;  // Monday, Wednesday, Sunday
  const Reminder w = make("2026-11-20T18:00", "Europe/Berlin", weekly);  // starts on a Friday
  CHECK(next_n(w, w.first_fire_utc_ms - 1, 4) ==
        std::vector<std::string>{"2026-11-22 18:00", "2026-11-23 18:00", "2026-11-25 18:00",
                                 "2026-11-29 18:00"});
  CHECK(format_local(*last_occurrence_at_or_before(w, local_to_utc_ms("2026-11-28T12:00",
                                                                     "Europe/Berlin")),
                     "Europe/Berlin") == "2026-11-25 18:00");
}

TEST_CASE("every N hours within a day window") {
  Recurrence rec = kind(Recurrence::Kind::kInterval);
  rec.interval_minutes = 240;
  rec.window_start_minute = 8 * 60;
  rec.window_end_minute = 20 * 60;  // exclusive: 08, 12, 16
  const Reminder r = make("2026-06-01T00:00", "Europe/Berlin", rec);
  CHECK(next_n(r, r.first_fire_utc_ms - 1, 5) ==
        std::vector<std::string>{"2026-06-01 08:00", "2026-06-01 12:00", "2026-06-01 16:00",
                                 "2026-06-02 08:00", "2026-06-02 12:00"});
  CHECK(format_local(*last_occurrence_at_or_before(r, local_to_utc_ms("2026-06-02T07:59",
                                                                     "Europe/Berlin")),
                     "Europe/Berlin") == "2026-06-01 16:00");
}

TEST_CASE("every 30 minutes through the spring gap and the autumn fold") {
  Recurrence rec = kind(Recurrence::Kind::kInterval);
  rec.interval_minutes = 30;
  rec.window_start_minute = 60;      // 01:00
  rec.window_end_minute = 4 * 60;    // 04:00
  const Reminder spring = make("2026-03-29T00:00", "Europe/Berlin", rec);
  // 02:00 and 02:30 do not exist: they collapse into one firing at 03:00.
  CHECK(next_n(spring, spring.first_fire_utc_ms, 5) ==
        std::vector<std::string>{"2026-03-29 01:00", "2026-03-29 01:30", "2026-03-29 03:00",
                                 "2026-03-29 03:30", "2026-03-30 01:00"});
  const Reminder autumn = make("2026-10-25T00:00", "Europe/Berlin", rec);
  std::vector<std::int64_t> utc;
  std::int64_t after = autumn.first_fire_utc_ms;
  for (int i = 0; i < 6; ++i) utc.push_back(after = *next_occurrence(autumn, after));
  // 01:00 01:30 02:00 02:30 (CEST, once each) 03:00 03:30 (CET): six slots, no repeats.
  CHECK(format_local(utc[0], "Europe/Berlin") == "2026-10-25 01:00");
  CHECK(format_local(utc[4], "Europe/Berlin") == "2026-10-25 03:00");
  CHECK(utc[4] - utc[3] == 90 * kMinute);  // 02:30 CEST -> 03:00 CET
  CHECK(format_local(*next_occurrence(autumn, utc[5]), "Europe/Berlin") == "2026-10-26 01:00");
}

TEST_CASE("invalid recurrences are refused with the field named") {
  Reminder r = make("2026-06-01T08:00", "UTC", kind(Recurrence::Kind::kWeekly));
  CHECK_THROWS_WITH(validate_reminder(r),
                    doctest::Contains("recurrence.weekdays: a weekly reminder needs days"));
  r.recurrence = kind(Recurrence::Kind::kInterval);
  CHECK_THROWS_WITH(validate_reminder(r), "recurrence.interval_minutes: expected 1..1440, got 0");
  r.recurrence.interval_minutes = 60;
  r.recurrence.window_start_minute = 600;
  r.recurrence.window_end_minute = 600;
  CHECK_THROWS_WITH(validate_reminder(r), doctest::Contains("recurrence.window"));
  r.recurrence = {};
  r.title.clear();
  CHECK_THROWS_WITH(validate_reminder(r), "title: a reminder needs a title");
}

TEST_CASE("a repeat as the carer writes it reads back the same (the web page's edit form)") {
  for (const auto& [repeat, window] : std::vector<std::pair<std::string, std::string>>{
           {"once", ""},
           {"daily", ""},
           {"weekdays", ""},
           {"weekly:mon,thu,sun", ""},
           {"every:240", "08:00-20:00"},
           {"every:30", "00:00-24:00"}}) {
    CAPTURE(repeat);
    const Recurrence r = parse_repeat(repeat, window);
    CHECK(format_repeat(r) == std::pair{repeat, window});
    CHECK(describe(parse_repeat(format_repeat(r).first, format_repeat(r).second)) == describe(r));
  }
  // The refusals name the field.
  CHECK_THROWS_WITH(parse_repeat("weekly:mon,xyz", ""),
                    "repeat: unknown day 'xyz' (expected mon,tue,wed,thu,fri,sat,sun)");
  CHECK_THROWS_WITH(parse_repeat("daily", "08:00-20:00"),
                    "window: only applies to repeat every:MINUTES");
}
