#include "data/recurrence.h"

#include <date/date.h>
#include <date/tz.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "common/local_time.h"

namespace marvin::data {
namespace {

using std::chrono::milliseconds;
using std::chrono::minutes;
using std::chrono::seconds;

const date::time_zone* zone_named(std::string_view name) {
  const date::time_zone* zone = find_time_zone(name);
  if (zone == nullptr) {
    throw std::runtime_error("time_zone: unknown IANA time zone '" + std::string(name) + "'");
  }
  return zone;
}

// Local time to UTC (the gap and fold rule is local_to_utc's), in ms as the store keeps it.
std::int64_t resolve(const date::time_zone* zone, LocalMs local) {
  return local_to_utc(*zone, local).time_since_epoch().count();
}

LocalMs to_local(const date::time_zone* zone, std::int64_t utc_ms) {
  return utc_to_local(*zone, UtcMs{milliseconds{utc_ms}});
}

// Monday = 0 ... Sunday = 6.
unsigned monday_based(date::local_days day) {
  return (date::weekday{day}.c_encoding() + 6) % 7;
}

bool day_allowed(const Recurrence& r, date::local_days day) {
  switch (r.kind) {
    case Recurrence::Kind::kDaily:
      return true;
    case Recurrence::Kind::kWeekdays:
      return monday_based(day) < 5;
    case Recurrence::Kind::kWeekly:
      return (r.weekdays >> monday_based(day)) & 1u;
    case Recurrence::Kind::kInterval:
      return r.weekdays == 0 || ((r.weekdays >> monday_based(day)) & 1u);
    case Recurrence::Kind::kOnce:
      return false;
  }
  return false;
}

// The occurrences on one local day, ascending in UTC.
void day_slots(const Reminder& r, const date::time_zone* zone, milliseconds time_of_day,
               date::local_days day, std::vector<std::int64_t>& out) {
  out.clear();
  if (!day_allowed(r.recurrence, day)) return;
  const LocalMs midnight{day};
  if (r.recurrence.kind == Recurrence::Kind::kInterval) {
    for (std::int32_t m = r.recurrence.window_start_minute; m < r.recurrence.window_end_minute;
         m += r.recurrence.interval_minutes) {
      const std::int64_t utc = resolve(zone, midnight + minutes{m});
      // Two slots in one spring gap resolve to the same instant: fire once.
      if (out.empty() || utc > out.back()) out.push_back(utc);
    }
  } else {
    out.push_back(resolve(zone, midnight + time_of_day));
  }
}

struct Walk {
  const date::time_zone* zone;
  milliseconds time_of_day;
  date::local_days first_day;
};

Walk start_walk(const Reminder& r) {
  validate_reminder(r);
  const date::time_zone* zone = zone_named(r.time_zone);
  const LocalMs first = to_local(zone, r.first_fire_utc_ms);
  const auto first_day = date::floor<date::days>(first);
  return {zone, first - first_day, first_day};
}

// Weekly reminders may skip six days; interval windows and time zones shift at most a day.
constexpr int kSearchDays = 9;

}  // namespace

void validate_reminder(const Reminder& r) {
  if (r.title.empty()) throw std::runtime_error("title: a reminder needs a title");
  zone_named(r.time_zone);
  const Recurrence& rec = r.recurrence;
  switch (rec.kind) {
    case Recurrence::Kind::kOnce:
    case Recurrence::Kind::kDaily:
    case Recurrence::Kind::kWeekdays:
      break;
    case Recurrence::Kind::kWeekly:
      if (rec.weekdays == 0 || rec.weekdays > 0x7f)
        throw std::runtime_error("recurrence.weekdays: a weekly reminder needs days in 1..127 "
                                 "(bit 0 = Monday), got " + std::to_string(rec.weekdays));
      break;
    case Recurrence::Kind::kInterval:
      if (rec.interval_minutes < 1 || rec.interval_minutes > 24 * 60)
        throw std::runtime_error("recurrence.interval_minutes: expected 1..1440, got " +
                                 std::to_string(rec.interval_minutes));
      if (rec.window_start_minute < 0 || rec.window_end_minute > 24 * 60 ||
          rec.window_start_minute >= rec.window_end_minute)
        throw std::runtime_error("recurrence.window: expected 0 <= start < end <= 1440 minutes, got " +
                                 std::to_string(rec.window_start_minute) + ".." +
                                 std::to_string(rec.window_end_minute));
      if (rec.weekdays > 0x7f)
        throw std::runtime_error("recurrence.weekdays: expected 0..127, got " +
                                 std::to_string(rec.weekdays));
      break;
    default:
      throw std::runtime_error("recurrence.kind: unknown kind " +
                               std::to_string(static_cast<int>(rec.kind)));
  }
}

std::optional<std::int64_t> next_occurrence(const Reminder& r, std::int64_t after_utc_ms) {
  if (r.recurrence.kind == Recurrence::Kind::kOnce) {
    validate_reminder(r);
    if (r.first_fire_utc_ms > after_utc_ms) return r.first_fire_utc_ms;
    return std::nullopt;
  }
  const Walk w = start_walk(r);
  // Nothing happens before the first occurrence.
  const std::int64_t bound = std::max(after_utc_ms, r.first_fire_utc_ms - 1);
  auto day = std::max(w.first_day, date::floor<date::days>(to_local(w.zone, bound)) - date::days{1});
  std::vector<std::int64_t> slots;
  for (int i = 0; i < kSearchDays + 2; ++i, day += date::days{1}) {
    day_slots(r, w.zone, w.time_of_day, day, slots);
    for (std::int64_t s : slots)
      if (s > bound) return s;
  }
  return std::nullopt;  // unreachable for a valid recurrence
}

std::optional<std::int64_t> last_occurrence_at_or_before(const Reminder& r,
                                                         std::int64_t at_utc_ms) {
  if (at_utc_ms < r.first_fire_utc_ms) return std::nullopt;
  if (r.recurrence.kind == Recurrence::Kind::kOnce) return r.first_fire_utc_ms;
  const Walk w = start_walk(r);
  auto day = date::floor<date::days>(to_local(w.zone, at_utc_ms)) + date::days{1};
  std::vector<std::int64_t> slots;
  for (int i = 0; i < kSearchDays + 2 && day >= w.first_day; ++i, day -= date::days{1}) {
    day_slots(r, w.zone, w.time_of_day, day, slots);
    for (auto it = slots.rbegin(); it != slots.rend(); ++it)
      if (*it <= at_utc_ms && *it >= r.first_fire_utc_ms) return *it;
  }
  return std::nullopt;
}

std::int64_t local_to_utc_ms(std::string_view text, std::string_view time_zone) {
  const date::time_zone* zone = zone_named(time_zone);
  int y = 0, mo = 0, d = 0, h = 0, mi = 0, s = 0, used = 0;
  const std::string copy(text);
  bool parsed = std::sscanf(copy.c_str(), "%4d-%2d-%2d%*1[T ]%2d:%2d%n", &y, &mo, &d, &h, &mi,
                            &used) == 5 && used == static_cast<int>(copy.size());
  if (!parsed) {
    used = 0;
    parsed = std::sscanf(copy.c_str(), "%4d-%2d-%2d%*1[T ]%2d:%2d:%2d%n", &y, &mo, &d, &h, &mi,
                         &s, &used) == 6 && used == static_cast<int>(copy.size());
  }
  const auto ymd = date::year{y} / date::month{static_cast<unsigned>(mo)} /
                   date::day{static_cast<unsigned>(d)};
  if (!parsed || !ymd.ok() || h < 0 || h > 23 || mi < 0 || mi > 59 || s < 0 || s > 59) {
    throw std::runtime_error("time '" + copy + "': expected local time YYYY-MM-DDTHH:MM");
  }
  const LocalMs local = LocalMs{date::local_days{ymd}} + std::chrono::hours{h} + minutes{mi} +
                        seconds{s};
  return resolve(zone, local);
}

std::string format_local(std::int64_t utc_ms, std::string_view time_zone) {
  const date::time_zone* zone = zone_named(time_zone);
  return date::format("%Y-%m-%d %H:%M", date::floor<minutes>(to_local(zone, utc_ms)));
}

std::string describe(const Recurrence& r) {
  static constexpr std::array<const char*, 7> kDays{"mon", "tue", "wed", "thu",
                                                    "fri", "sat", "sun"};
  auto days = [&] {
    std::string out;
    for (unsigned i = 0; i < 7; ++i)
      if ((r.weekdays >> i) & 1u) {
        if (!out.empty()) out += ',';
        out += kDays[i];
      }
    return out;
  };
  auto hhmm = [](std::int32_t m) {
    char buf[8];
    std::snprintf(buf, sizeof buf, "%02d:%02d", (m / 60) % 100, m % 60);
    return std::string(buf);
  };
  switch (r.kind) {
    case Recurrence::Kind::kOnce: return "once";
    case Recurrence::Kind::kDaily: return "daily";
    case Recurrence::Kind::kWeekdays: return "weekdays";
    case Recurrence::Kind::kWeekly: return "weekly " + days();
    case Recurrence::Kind::kInterval: {
      std::string out = "every " + std::to_string(r.interval_minutes) + " min " +
                        hhmm(r.window_start_minute) + "-" + hhmm(r.window_end_minute);
      if (r.weekdays != 0) out += " on " + days();
      return out;
    }
  }
  return "?";
}

namespace {

std::int32_t parse_hhmm(const std::string& text, const std::string& what) {
  int h = -1, m = -1, used = 0;
  if (std::sscanf(text.c_str(), "%2d:%2d%n", &h, &m, &used) != 2 ||
      used != static_cast<int>(text.size()) || h < 0 || h > 24 || m < 0 || m > 59 ||
      h * 60 + m > 24 * 60)
    throw std::runtime_error(what + ": '" + text + "' is not a time of day HH:MM");
  return h * 60 + m;
}

}  // namespace

std::pair<std::string, std::string> format_repeat(const Recurrence& r) {
  static const char* kDayNames[] = {"mon", "tue", "wed", "thu", "fri", "sat", "sun"};
  auto hhmm = [](std::int32_t minute) {
    char text[8];
    std::snprintf(text, sizeof text, "%02d:%02d", minute / 60 % 100, minute % 60);
    return std::string(text);
  };
  switch (r.kind) {
    case Recurrence::Kind::kOnce:
      return {"once", ""};
    case Recurrence::Kind::kDaily:
      return {"daily", ""};
    case Recurrence::Kind::kWeekdays:
      return {"weekdays", ""};
    case Recurrence::Kind::kWeekly: {
      std::string days;
      for (int i = 0; i < 7; ++i)
        if (r.weekdays & (1u << i)) days += (days.empty() ? "" : ",") + std::string(kDayNames[i]);
      return {"weekly:" + days, ""};
    }
    case Recurrence::Kind::kInterval:
      return {"every:" + std::to_string(r.interval_minutes),
              hhmm(r.window_start_minute) + "-" + hhmm(r.window_end_minute)};
  }
  return {"once", ""};
}

Recurrence parse_repeat(std::string_view repeat_text, std::string_view window_text) {
  const std::string repeat(repeat_text), window(window_text);
  Recurrence r;
  static const char* kDays[] = {"mon", "tue", "wed", "thu", "fri", "sat", "sun"};
  if (repeat == "once") {
    r.kind = Recurrence::Kind::kOnce;
  } else if (repeat == "daily") {
    r.kind = Recurrence::Kind::kDaily;
  } else if (repeat == "weekdays") {
    r.kind = Recurrence::Kind::kWeekdays;
  } else if (repeat.rfind("weekly:", 0) == 0) {
    r.kind = Recurrence::Kind::kWeekly;
    std::stringstream days(repeat.substr(7));
    for (std::string day; std::getline(days, day, ',');) {
      int index = -1;
      for (int i = 0; i < 7; ++i)
        if (day == kDays[i]) index = i;
      if (index < 0)
        throw std::runtime_error("repeat: unknown day '" + day +
                                 "' (expected mon,tue,wed,thu,fri,sat,sun)");
      r.weekdays = static_cast<std::uint8_t>(r.weekdays | (1u << index));
    }
  } else if (repeat.rfind("every:", 0) == 0) {
    r.kind = Recurrence::Kind::kInterval;
    const std::string minutes = repeat.substr(6);
    if (minutes.empty() || minutes.find_first_not_of("0123456789") != std::string::npos ||
        minutes.size() > 4)
      throw std::runtime_error("repeat: 'every:' needs a number of minutes, got '" + minutes +
                               "'");
    r.interval_minutes = std::stoi(minutes);
  } else {
    throw std::runtime_error("repeat: unknown '" + repeat +
                             "' (expected once, daily, weekdays, weekly:mon,thu or "
                             "every:MINUTES)");
  }
  if (!window.empty()) {
    if (r.kind != Recurrence::Kind::kInterval)
      throw std::runtime_error("window: only applies to repeat every:MINUTES");
    const auto dash = window.find('-');
    if (dash == std::string::npos) throw std::runtime_error("window: expected HH:MM-HH:MM");
    r.window_start_minute = parse_hhmm(window.substr(0, dash), "window");
    r.window_end_minute = parse_hhmm(window.substr(dash + 1), "window");
  }
  return r;
}

}  // namespace marvin::data
