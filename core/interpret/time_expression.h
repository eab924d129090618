// Spoken date/time expressions -> a structured phrase (no clock involved yet).
//
// Supported (tokens as normalised, so "eight" is "8"):
//   time of day   "8", "at 8", "8 pm", "8 o'clock", "7:30", "7 30", "8 oh 5", "noon",
//                 "midnight", "half past 8", "quarter past 8", "quarter to 9", "10 past 8",
//                 "20 minutes to 9", "8 in the morning/afternoon/evening", "10 at night"
//   day           "today", "tonight" (evening hours), "tomorrow", "the day after tomorrow",
//                 "monday", "on monday", "next monday", "this monday"
//   calendar date "march 3rd", "on march 3", "the 3rd of march", "3 march", "march the 3rd",
//                 "mar 3", "sept 21st", "the 20 1st of may" (as normalised), each with an
//                 optional year ("march 4th 2027"); "may" only with a day number. Numeric
//                 dates ("12/03/2019") are not read: day/month or month/day is ambiguous.
//   holiday       "christmas [day|eve]", "boxing day", "new year's [day|eve]", "halloween",
//                 "valentine's day": their calendar dates (Easter, which moves, is not read)
//   day range     "this week", "next week", "this weekend", "next weekend" (no time of day;
//                 resolved against the clock: the weeks run Monday to Sunday)
//   relative      "in 20 minutes", "in an hour and a half" (nothing else may follow)
//   part of day   "morning", "in the afternoon", "this evening", "at night", beside a day or a
//                 recurrence ("tomorrow morning", "monday evening", "every morning"): an
//                 hour without am/pm is read in that half of the day, and with no time it
//                 means 09:00 (morning), 15:00, 19:00 or 21:00 (night)
//   recurrence    "every day", "daily", "each day", "every weekday", "on weekdays",
//                 "every monday [and wednesday]", "on mondays", "every weekend",
//                 "every morning/evening/night" (daily), "every 2 hours", "every hour",
//                 "every 30 minutes" (interval)
// Parts may come in either order ("tomorrow at 9", "at 9 tomorrow", "at 10 on monday").
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace marvin::interpret {

struct TimeOfDay {
  int hour = 0;    // 0..23; for an ambiguous hour, the morning reading (1..11)
  int minute = 0;  // 0..59
  bool ambiguous = false;  // "at 8": 08:00 or 20:00 (no am/pm, no 24-hour clue)
};

enum class RecurrenceKind { kOnce, kDaily, kWeekdays, kWeekly, kInterval };

enum class DayRange { kNone, kThisWeek, kNextWeek, kThisWeekend, kNextWeekend };

struct TimePhrase {
  RecurrenceKind kind = RecurrenceKind::kOnce;
  std::optional<TimeOfDay> time;            // absent: the day's default time (09:00)
  std::optional<int> day_offset;            // today = 0, tomorrow = 1, ... (kOnce only)
  bool evening = false;                     // "tonight": ambiguous hours read as pm
  bool morning = false;                     // "tomorrow morning": ambiguous hours read as am
  int default_hour = 0;                     // a part of the day's hour without a time; 0: none
  unsigned weekday_mask = 0;                // bit d = weekday d (0 = Sunday ... 6 = Saturday)
  std::optional<std::int64_t> in_seconds;   // "in 20 minutes" (kOnce, nothing else)
  std::int64_t every_seconds = 0;           // kInterval
  DayRange range = DayRange::kNone;         // "next week" (kOnce, no time of day)
  int month = 0;                            // calendar date (kOnce): 1..12, 0 = none
  int day_of_month = 0;                     // 1..31 with a month
  int year = 0;                             // 0 = not said
  // A feast that moves with Easter (kOnce): days from Easter Sunday ("good friday" -2).
  std::optional<int> days_from_easter;

  // A calendar date was said: a month and day, or a feast counted from Easter.
  bool dated() const { return month != 0 || days_from_easter.has_value(); }
};

// The whole span must be one expression; nullopt otherwise.
std::optional<TimePhrase> parse_time_phrase(std::span<const std::string> words);

// One expression, or two times of day joined by "and" that share the day or recurrence
// one of them names: "every day at 9 am and 9 pm", "tomorrow at 8 and at 6",
// "every morning and evening". Empty when the span is neither.
std::vector<TimePhrase> parse_time_phrases(std::span<const std::string> words);

// "sunday" ... "saturday" for 0..6.
const char* weekday_name(int weekday);

}  // namespace marvin::interpret
