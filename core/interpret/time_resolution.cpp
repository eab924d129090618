#include "interpret/time_resolution.h"

#include <chrono>
#include <cstdio>
#include <stdexcept>
#include <utility>

#include <date/date.h>
#include <date/tz.h>

#include "common/local_time.h"

namespace marvin::interpret {
namespace {

using std::chrono::hours;
using std::chrono::milliseconds;
using std::chrono::minutes;

constexpr int kDefaultHour = 9;

const date::time_zone* find_zone(const std::string& name) {
  const date::time_zone* zone = find_time_zone(name);
  if (zone == nullptr) {
    throw std::runtime_error("unknown time zone \"" + name +
                             "\" in Context::time_zone (expected an IANA name such as "
                             "\"Europe/Berlin\")");
  }
  return zone;
}

std::string format_local(LocalMs local) {
  auto day = date::floor<date::days>(local);
  date::year_month_day ymd{day};
  auto since_midnight = date::floor<minutes>(local - day);
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%04d-%02u-%02uT%02d:%02d", static_cast<int>(ymd.year()),
                static_cast<unsigned>(ymd.month()), static_cast<unsigned>(ymd.day()),
                static_cast<int>(since_midnight.count() / 60),
                static_cast<int>(since_midnight.count() % 60));
  return buffer;
}

std::string format_hh_mm(int hour, int minute) {
  char buffer[8];
  std::snprintf(buffer, sizeof buffer, "%02d:%02d", hour, minute);
  return buffer;
}

class Resolver {
 public:
  Resolver(std::int64_t now_utc_ms, const std::string& zone_name)
      : zone_(find_zone(zone_name)), now_(milliseconds(now_utc_ms)) {
    today_ = date::floor<date::days>(utc_to_local(*zone_, now_));
  }

  // The instant of `hour:minute` on `day`, local; gaps resolve to the transition.
  UtcMs instant(date::local_days day, int hour, int minute) const {
    LocalMs local{day + hours(hour) + minutes(minute)};
    return local_to_utc(*zone_, local);
  }

  // The first instant after now at hour:minute on one of the days today+first..today+last
  // whose weekday is in `mask` (0 = any).
  std::optional<UtcMs> first_after_now(int first, int last, unsigned mask, int hour,
                                       int minute) const {
    for (int offset = first; offset <= last; ++offset) {
      date::local_days day = today_ + date::days(offset);
      unsigned weekday = date::weekday(day).c_encoding();
      if (mask != 0 && (mask & (1U << weekday)) == 0) continue;
      UtcMs at = instant(day, hour, minute);
      if (at > now_) return at;
    }
    return std::nullopt;
  }

  // First day (offset from today) and length of a day range; weeks run Monday..Sunday.
  std::pair<int, int> range_days(DayRange range) const {
    const int monday_based = static_cast<int>((date::weekday(today_).c_encoding() + 6) % 7);
    const int next_monday = 7 - monday_based;
    switch (range) {
      case DayRange::kThisWeek:
        // On a Sunday the week is all but over: "this week" is today and the coming week.
        if (monday_based == 6) return {0, 8};
        return {0, 7 - monday_based};
      case DayRange::kNextWeek:
        return {next_monday, 7};
      case DayRange::kThisWeekend:
        if (monday_based == 6) return {0, 1};  // Sunday: the rest of this weekend
        if (monday_based == 5) return {0, 2};
        return {5 - monday_based, 2};
      case DayRange::kNextWeekend:
        return {next_monday + 5, 2};
      case DayRange::kNone:
        break;
    }
    return {0, 1};
  }

  // The first instant after now at hour:minute on month/day (of `year`, or of this year or
  // the next when 0); today without a time said is now. nullopt for a day the month lacks.
  std::optional<UtcMs> calendar_date(int year, int month, int day, int hour, int minute,
                                     bool time_given) const {
    return yearly(
        year,
        [&](int y) -> std::optional<date::local_days> {
          const date::year_month_day ymd{date::year(y), date::month(static_cast<unsigned>(month)),
                                         date::day(static_cast<unsigned>(day))};
          if (!ymd.ok()) return std::nullopt;  // Feb 29 in a common year: try the next
          return date::local_days{ymd};
        },
        hour, minute, time_given);
  }

  // The first of the days `day_in(year)` names that is still ahead, from this year on (only
  // in `year` when one was said); today counts when no time was said.
  template <typename DayIn>
  std::optional<UtcMs> yearly(int year, DayIn day_in, int hour, int minute,
                              bool time_given) const {
    const date::year_month_day today{today_};
    const int first_year = year != 0 ? year : static_cast<int>(today.year());
    const int last_year = year != 0 ? year : first_year + 4;  // Feb 29: a leap year
    for (int y = first_year; y <= last_year; ++y) {
      const std::optional<date::local_days> local_day = day_in(y);
      if (!local_day) continue;
      UtcMs at = instant(*local_day, hour, minute);
      if (at > now_) return at;
      if (*local_day == today_ && !time_given) return now_;
    }
    return std::nullopt;
  }

  LocalMs local(UtcMs at) const { return utc_to_local(*zone_, at); }
  UtcMs now() const { return now_; }
  const date::time_zone* zone() const { return zone_; }

 private:
  const date::time_zone* zone_;
  UtcMs now_;
  date::local_days today_;
};

// Easter Sunday of the Gregorian calendar (the anonymous Gregorian algorithm, as in
// Meeus, "Astronomical Algorithms", ch. 8).
date::local_days easter_sunday(int year) {
  const int a = year % 19, b = year / 100, c = year % 100, d = b / 4, e = b % 4;
  const int f = (b + 8) / 25, g = (b - f + 1) / 3, h = (19 * a + b - d - g + 15) % 30;
  const int i = c / 4, k = c % 4, l = (32 + 2 * e + 2 * i - h - k) % 7;
  const int m = (a + 11 * h + 22 * l) / 451;
  const int month = (h + l - 7 * m + 114) / 31, day = (h + l - 7 * m + 114) % 31 + 1;
  return date::local_days{date::year(year) / date::month(static_cast<unsigned>(month)) /
                          date::day(static_cast<unsigned>(day))};
}

nlohmann::json weekday_list(unsigned mask) {
  nlohmann::json list = nlohmann::json::array();
  for (int d = 1; d <= 7; ++d) {  // Monday first, Sunday last
    int weekday = d % 7;
    if ((mask & (1U << weekday)) != 0) list.push_back(weekday_name(weekday));
  }
  return list;
}

}  // namespace

std::optional<nlohmann::json> resolve_time_phrase(const TimePhrase& phrase,
                                                  std::int64_t now_utc_ms,
                                                  const std::string& time_zone) {
  Resolver resolver(now_utc_ms, time_zone);
  nlohmann::json recurrence = {{"kind", "once"}};
  std::optional<UtcMs> at;
  int range_days = 0;

  if (phrase.in_seconds) {
    at = resolver.now() + std::chrono::seconds(*phrase.in_seconds);
  } else if (phrase.kind == RecurrenceKind::kInterval) {
    at = resolver.now() + std::chrono::seconds(phrase.every_seconds);
    recurrence = {{"kind", "interval"}, {"every_seconds", phrase.every_seconds}};
  } else {
    int hour = phrase.default_hour != 0 ? phrase.default_hour : kDefaultHour, minute = 0;
    bool both_readings = false;
    if (phrase.time) {
      hour = phrase.time->hour;
      minute = phrase.time->minute;
      if (phrase.time->ambiguous) {
        if (phrase.evening) {
          hour += 12;
        } else if (phrase.morning) {
          // the morning reading, as parsed
        } else if (phrase.kind == RecurrenceKind::kOnce && !phrase.day_offset &&
                   phrase.weekday_mask == 0 && !phrase.dated() && hour > 6) {
          both_readings = true;
        } else if (hour <= 6) {
          // 1..6 is the afternoon, with a day or without: "remind me to call the bank at 3"
          // said at 10 PM is 3 PM tomorrow, not a reminder that wakes the owner at 3 AM.
          // (An alarm's "wake me at 5" was read as morning above.)
          hour += 12;
        }
      }
    }
    switch (phrase.kind) {
      case RecurrenceKind::kOnce:
        if (phrase.range != DayRange::kNone) {
          // The first day's default hour, or now when that has passed (today is in range).
          const auto [first, count] = resolver.range_days(phrase.range);
          range_days = count;
          at = resolver.first_after_now(first, first, 0, hour, minute);
          if (!at) at = resolver.now();
        } else if (phrase.days_from_easter) {
          at = resolver.yearly(
              phrase.year,
              [&](int y) -> std::optional<date::local_days> {
                return easter_sunday(y) + date::days(*phrase.days_from_easter);
              },
              hour, minute, phrase.time.has_value());
        } else if (phrase.month != 0) {
          at = resolver.calendar_date(phrase.year, phrase.month, phrase.day_of_month, hour,
                                      minute, phrase.time.has_value());
        } else if (phrase.day_offset) {
          int day = *phrase.day_offset;
          at = resolver.first_after_now(day, day, 0, hour, minute);
        } else if (phrase.weekday_mask != 0) {
          at = resolver.first_after_now(0, 7, phrase.weekday_mask, hour, minute);
        } else {
          at = resolver.first_after_now(0, 1, 0, hour, minute);
          if (both_readings) {
            auto pm = resolver.first_after_now(0, 1, 0, hour + 12, minute);
            if (pm && (!at || *pm < *at)) at = pm;
          }
        }
        break;
      case RecurrenceKind::kDaily:
        at = resolver.first_after_now(0, 1, 0, hour, minute);
        recurrence = {{"kind", "daily"}, {"time", format_hh_mm(hour, minute)}};
        break;
      case RecurrenceKind::kWeekdays:
      case RecurrenceKind::kWeekly:
        at = resolver.first_after_now(0, 7, phrase.weekday_mask, hour, minute);
        recurrence = {
            {"kind", phrase.kind == RecurrenceKind::kWeekdays ? "weekdays" : "weekly"},
            {"weekdays", weekday_list(phrase.weekday_mask)},
            {"time", format_hh_mm(hour, minute)}};
        break;
      case RecurrenceKind::kInterval:
        break;
    }
  }
  if (!at) return std::nullopt;
  nlohmann::json value{
      {"at", format_local(resolver.local(*at))},
      {"utc_ms", at->time_since_epoch().count()},
      {"time_zone", time_zone},
      {"time_given", phrase.time.has_value() || phrase.in_seconds.has_value() ||
                         phrase.kind == RecurrenceKind::kInterval},
      // "to 3 pm" names no day, "to Friday at 3" does: moving an appointment keeps its own
      // day in the first case (the schedule skill).
      {"day_given", phrase.kind != RecurrenceKind::kOnce || phrase.day_offset.has_value() ||
                        phrase.weekday_mask != 0 || phrase.dated() ||
                        phrase.range != DayRange::kNone || phrase.in_seconds.has_value()},
      {"recurrence", recurrence}};
  if (range_days > 0) value["days"] = range_days;
  return value;
}

}  // namespace marvin::interpret
