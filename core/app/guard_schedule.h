// Guard mode by schedule (issue 22): "every night at 10 pm", "on weekdays from 9 to 5".
//
// A schedule is kept as recurring reminders in the reminders store (SQLite, so it survives a
// restart), created by kGuardStorageId ("host.guard"): one titled "guard mode on: <when>" at
// the start and, for a window, one titled "guard mode off: <when>" at its end. The reminder
// scheduler fires them (time zones, daylight saving, what was due while Marvin was off) and
// the host turns guard mode on or off instead of announcing them (`apply_guard_firing`). A
// window's end turns it off "by the schedule" even without a known face: the household set it.
// `marvin guard schedule add|list|cancel` (cli_guard.cpp) edits them; `marvin schedule list`
// shows them too.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "data/personal_data.h"

namespace marvin::skills {
class Guard;
}

namespace marvin::app {

struct GuardPlan {
  std::uint8_t days = 0x7f;       // bit 0 = Monday ... bit 6 = Sunday
  int on_minute = 0;              // local minute of the day guard mode comes on
  std::optional<int> off_minute;  // a window's end (may be the next day: 22:00 to 07:00)
  std::string when;               // as given, lower case: "every night at 10 pm"
};

// Parses "every night at 10 pm", "every day at 22:30", "on weekdays from 9 to 5",
// "on mondays and fridays from 8 am to 1 pm", "weekends at noon". Days: every day / night /
// evening, daily, nightly, weekdays, weekends, monday ... sunday (plurals, "and", commas).
// Times: 1 to 12 with am/pm, 0:00 to 23:59, noon, midnight; in "from 9 to 5" a bare end
// hour not after the start is taken in the afternoon (17:00). Throws std::invalid_argument
// naming the word that is wrong and what was expected.
GuardPlan parse_guard_plan(std::string_view text);

// The reminders of `plan` in `time_zone` (validated), their first occurrence after
// `now_utc_ms`.
std::vector<data::Reminder> guard_plan_reminders(const GuardPlan& plan,
                                                 const std::string& time_zone,
                                                 std::int64_t now_utc_ms);

// Whether `r` is a guard schedule's: true for "on", false for "off", nullopt for any other.
std::optional<bool> guard_switch(const data::Reminder& r);

// Turns `guard` on or off for a firing of a guard schedule's reminder (`by` "the schedule");
// returns the sentence to say, or nullopt when `r` is not a guard schedule's.
std::optional<std::string> apply_guard_firing(const data::Reminder& r, skills::Guard* guard);

inline constexpr const char* kGuardOnTitle = "guard mode on: ";
inline constexpr const char* kGuardOffTitle = "guard mode off: ";
inline constexpr const char* kOffBySchedule = "the schedule";

}  // namespace marvin::app
