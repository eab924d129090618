// A parsed time phrase + the clock and time zone -> the slot value of a datetime slot:
//   {"at":"YYYY-MM-DDTHH:MM", "utc_ms":N, "time_zone":"Europe/Berlin", "time_given":true,
//    "day_given":false, "recurrence":{"kind":"once"}}
//   recurrence kinds: {"kind":"daily","time":"08:00"},
//     {"kind":"weekdays","weekdays":["monday",...,"friday"],"time":"07:30"},
//     {"kind":"weekly","weekdays":["monday"],"time":"10:00"},
//     {"kind":"interval","every_seconds":7200}
//
//   a day range ("next week", "this weekend") adds "days":N; "at" is then its first day
//   (09:00, or now when the range starts today after 09:00). "This week" said on a Sunday
//   is today and the coming week (8 days): the week that is ending has no days left.
//
//   Two times of one day ("every day at 9 am and 9 pm", parse_time_phrases) are the first
//   one's value with "also": [the second's value] (the datetime slot parser adds it).
//
// "at" is the first occurrence strictly after now, as local wall time. Rules:
// - An ambiguous hour ("at 8") on its own is the next of 08:00 / 20:00. With a day or a
//   recurrence it reads 7..11 as morning and 1..6 as afternoon ("tomorrow at 3" = 15:00);
//   "tonight" reads it as evening.
// - No time of day ("tomorrow", "every monday") means 09:00, with "time_given": false.
// - "day_given" is false when only a time of day was said ("at 3 pm": the next 3 PM),
//   true for a day, a weekday, a date, a range, a recurrence or "in 20 minutes".
// - A local time that does not exist (spring-forward gap) resolves to the instant of the
//   transition (02:30 -> 03:00 in Europe/Berlin); a repeated one (fall-back) to its first
//   occurrence.
// - "today at 8" when 8 has passed is not a time (nullopt), and neither is a weekday that
//   would need more than a week.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "interpret/time_expression.h"

namespace marvin::interpret {

// Throws std::runtime_error naming the zone if `time_zone` is not a known IANA zone.
std::optional<nlohmann::json> resolve_time_phrase(const TimePhrase& phrase,
                                                  std::int64_t now_utc_ms,
                                                  const std::string& time_zone);

}  // namespace marvin::interpret
