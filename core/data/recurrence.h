// When a reminder fires: recurrence arithmetic in the owner's time zone.
//
// A reminder's occurrences are the slots of its Recurrence at or after its first
// occurrence (first_fire_utc_ms), computed in local time of its IANA time zone and then
// mapped to UTC:
//   kOnce      first_fire_utc_ms itself.
//   kDaily     every day at the local time of day of first_fire_utc_ms.
//   kWeekdays  Monday to Friday at that time.
//   kWeekly    on the days of `weekdays` (bit 0 = Monday) at that time.
//   kInterval  every `interval_minutes` from window_start_minute (inclusive) to
//              window_end_minute (exclusive), local minutes of the day; on every day, or
//              only on the days of `weekdays` when it is not 0.
// Daylight saving: a local time that does not exist (the spring gap, 02:30 in Berlin on
// the last Sunday of March) fires at the first valid instant after the gap (03:00 local);
// a local time that happens twice (the autumn fold) fires once, at its first occurrence.
// Times of day are kept to the second of first_fire_utc_ms.
//
// All functions are pure and thread-safe; they throw std::runtime_error naming the field
// when a reminder is invalid (unknown time zone, empty weekday set, bad window).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <utility>

#include "data/personal_data.h"

namespace marvin::data {

// Throws std::runtime_error naming the field if `reminder` cannot be scheduled: empty
// title, unknown time zone, weekday mask empty or above 0x7f, interval not in 1..1440,
// window outside 0..1440 or empty.
void validate_reminder(const Reminder& reminder);

// The first occurrence strictly after `after_utc_ms`, or nullopt if there is none (a
// one-off reminder that already happened).
std::optional<std::int64_t> next_occurrence(const Reminder& reminder, std::int64_t after_utc_ms);

// The last occurrence at or before `at_utc_ms`, or nullopt if none happened yet.
std::optional<std::int64_t> last_occurrence_at_or_before(const Reminder& reminder,
                                                         std::int64_t at_utc_ms);

// Local wall time "YYYY-MM-DDTHH:MM" (or with ":SS") in `time_zone` to UTC milliseconds,
// with the same daylight-saving rules as occurrences. Throws naming the text if it is
// not such a time or the zone is unknown.
std::int64_t local_to_utc_ms(std::string_view local_time, std::string_view time_zone);

// UTC milliseconds to local "YYYY-MM-DD HH:MM" in `time_zone` (for lists and speech).
std::string format_local(std::int64_t utc_ms, std::string_view time_zone);

// "once", "daily", "weekdays", "weekly mon,wed", "every 240 min 08:00-20:00".
std::string describe(const Recurrence& recurrence);

// How the carer writes a repeat (`marvin schedule add --repeat`, the web page's form):
// once | daily | weekdays | weekly:mon,thu | every:MINUTES, with `window` "HH:MM-HH:MM"
// (end exclusive) only for every:MINUTES. Throws std::runtime_error starting with the field
// ("repeat: ...", "window: ...") and saying what was expected.
Recurrence parse_repeat(std::string_view repeat, std::string_view window);
// The other way: the `repeat` and `window` parse_repeat takes back to `recurrence` (window
// empty unless every:MINUTES), so an edit form starts from what is stored.
std::pair<std::string, std::string> format_repeat(const Recurrence& recurrence);

}  // namespace marvin::data
