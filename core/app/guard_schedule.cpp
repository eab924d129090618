#include "app/guard_schedule.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <stdexcept>

#include "data/recurrence.h"
#include "skills/guard.h"

namespace marvin::app {
namespace {

std::vector<std::string> plan_words(std::string_view text) {
  std::vector<std::string> words;
  std::string word;
  for (char c : text) {
    const char l = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (l == ' ' || l == ',' || l == '\t' || l == '.' || l == '?' || l == '!') {
      if (!word.empty()) words.push_back(std::move(word));
      word.clear();
    } else {
      word += l;
    }
  }
  if (!word.empty()) words.push_back(std::move(word));
  return words;
}

// A day word's bits (Monday = bit 0), 0 for a filler word; throws for anything else.
std::uint8_t plan_day_bits(const std::string& w) {
  static const char* kDays[] = {"monday", "tuesday",  "wednesday", "thursday",
                                "friday", "saturday", "sunday"};
  for (int i = 0; i < 7; ++i) {
    const std::string d = kDays[i];
    if (w == d || w == d + "s") return static_cast<std::uint8_t>(1 << i);
  }
  if (w == "day" || w == "days" || w == "night" || w == "nights" || w == "evening" ||
      w == "evenings" || w == "daily" || w == "nightly") {
    return 0x7f;
  }
  if (w == "weekday" || w == "weekdays") return 0x1f;
  if (w == "weekend" || w == "weekends") return 0x60;
  if (w == "every" || w == "on" || w == "and" || w == "each" || w == "the") return 0;
  throw std::invalid_argument("unknown day '" + w +
                              "' (expected monday to sunday, weekdays, weekends, every day or "
                              "every night)");
}

struct PlanTime {
  int minute = 0;
  bool half_day = false;  // said with am/pm (or noon/midnight)
  int hour = 0;
};

// A time at words[i] ("10", "10:30", "10pm", "10 pm", "22:00", "noon"); advances i.
PlanTime plan_time(const std::vector<std::string>& words, std::size_t& i) {
  if (i >= words.size()) throw std::invalid_argument("a time is missing at the end");
  const std::size_t first = i;
  std::string w = words[i++];
  if (w == "noon" || w == "midday") return {12 * 60, true, 12};
  if (w == "midnight") return {0, true, 0};
  std::string suffix;
  for (const char* s : {"am", "pm", "a.m", "p.m"}) {
    const std::string x = s;
    if (w.size() > x.size() && w.compare(w.size() - x.size(), x.size(), x) == 0) {
      suffix = x.substr(0, 1);
      w.resize(w.size() - x.size());
      break;
    }
  }
  if (suffix.empty() && i < words.size()) {
    const std::string& next = words[i];
    if (next == "am" || next == "pm" || next == "a.m" || next == "p.m" || next == "o'clock") {
      if (next != "o'clock") suffix = next.substr(0, 1);
      ++i;
    }
  }
  std::string shown;  // the words of the time as given: "25 pm"
  for (std::size_t k = first; k < i; ++k) shown += (shown.empty() ? "" : " ") + words[k];
  int hour = -1, minute = 0;
  const auto colon = w.find(':');
  auto digits = [](const std::string& s) {
    return !s.empty() && s.size() <= 2 && std::all_of(s.begin(), s.end(), [](char c) {
      return std::isdigit(static_cast<unsigned char>(c));
    });
  };
  const std::string h = w.substr(0, colon),
                    m = colon == std::string::npos ? "" : w.substr(colon + 1);
  if (!digits(h) || (colon != std::string::npos && (!digits(m) || m.size() != 2))) {
    throw std::invalid_argument("'" + shown +
                                "' is not a time (expected e.g. 10 pm, 9:30 am or 22:00)");
  }
  hour = std::stoi(h);
  if (!m.empty()) minute = std::stoi(m);
  if (minute > 59)
    throw std::invalid_argument("'" + shown + "' is not a time (minutes are 00 to 59)");
  if (!suffix.empty()) {
    if (hour < 1 || hour > 12) {
      throw std::invalid_argument("'" + shown +
                                  "' is not a time (with am or pm the hour is 1 to 12)");
    }
    hour = hour % 12 + (suffix == "p" ? 12 : 0);
    return {hour * 60 + minute, true, hour};
  }
  if (hour > 23) throw std::invalid_argument("'" + shown + "' is not a time (hours are 0 to 23)");
  return {hour * 60 + minute, false, hour};
}

std::string plan_hhmm(int minute) {
  char text[32];
  std::snprintf(text, sizeof text, "%02d:%02d", minute / 60, minute % 60);
  return text;
}

data::Recurrence plan_recurrence(std::uint8_t days) {
  data::Recurrence r;
  if (days == 0x7f) {
    r.kind = data::Recurrence::Kind::kDaily;
  } else if (days == 0x1f) {
    r.kind = data::Recurrence::Kind::kWeekdays;
  } else {
    r.kind = data::Recurrence::Kind::kWeekly;
    r.weekdays = days;
  }
  return r;
}

bool starts_with(const std::string& s, const char* prefix) { return s.rfind(prefix, 0) == 0; }

}  // namespace

GuardPlan parse_guard_plan(std::string_view text) {
  const std::vector<std::string> words = plan_words(text);
  GuardPlan plan;
  for (const auto& w : words) plan.when += (plan.when.empty() ? "" : " ") + w;
  std::size_t i = 0;
  std::uint8_t days = 0;
  for (; i < words.size() && words[i] != "at" && words[i] != "from"; ++i) {
    days = static_cast<std::uint8_t>(days | plan_day_bits(words[i]));
  }
  if (i == words.size()) {
    throw std::invalid_argument("when? expected 'at 10 pm' or 'from 9 to 5' in '" + plan.when +
                                "'");
  }
  plan.days = days == 0 ? 0x7f : days;
  const bool window = words[i++] == "from";
  const PlanTime start = plan_time(words, i);
  plan.on_minute = start.minute;
  if (window) {
    if (i >= words.size() || (words[i] != "to" && words[i] != "until" && words[i] != "till")) {
      throw std::invalid_argument("'from " + plan_hhmm(start.minute) +
                                  "' needs an end: expected 'to' and a time");
    }
    ++i;
    PlanTime end = plan_time(words, i);
    // "from 9 to 5": a bare end hour not after the start is in the afternoon.
    if (!end.half_day && end.hour >= 1 && end.hour <= 12 && end.minute <= start.minute &&
        end.minute + 12 * 60 > start.minute) {
      end.minute += 12 * 60;
    }
    if (end.minute == start.minute) {
      throw std::invalid_argument("the window from " + plan_hhmm(start.minute) + " to " +
                                  plan_hhmm(end.minute) + " is empty");
    }
    plan.off_minute = end.minute;
  }
  if (i < words.size()) {
    throw std::invalid_argument("unexpected '" + words[i] + "' after the time");
  }
  return plan;
}

std::vector<data::Reminder> guard_plan_reminders(const GuardPlan& plan,
                                                 const std::string& time_zone,
                                                 std::int64_t now_utc_ms) {
  const std::string today = data::format_local(now_utc_ms, time_zone).substr(0, 10);
  auto make = [&](const char* title, int minute, std::uint8_t days) {
    data::Reminder r;
    r.title = title + plan.when;
    r.time_zone = time_zone;
    r.recurrence = plan_recurrence(days);
    r.created_by = skills::kGuardStorageId;
    r.first_fire_utc_ms = data::local_to_utc_ms(today + "T" + plan_hhmm(minute), time_zone);
    data::validate_reminder(r);
    const auto next = data::next_occurrence(r, now_utc_ms);
    if (!next) throw std::invalid_argument("the schedule '" + plan.when + "' never comes");
    r.next_fire_utc_ms = *next;
    return r;
  };
  std::vector<data::Reminder> out{make(kGuardOnTitle, plan.on_minute, plan.days)};
  if (plan.off_minute) {
    // A window past midnight ends on the next day: Monday 22:00 to Tuesday 07:00.
    const std::uint8_t days =
        *plan.off_minute > plan.on_minute
            ? plan.days
            : static_cast<std::uint8_t>(((plan.days << 1) | (plan.days >> 6)) & 0x7f);
    out.push_back(make(kGuardOffTitle, *plan.off_minute % (24 * 60), days));
  }
  return out;
}

std::optional<bool> guard_switch(const data::Reminder& r) {
  if (r.created_by != skills::kGuardStorageId) return std::nullopt;
  if (starts_with(r.title, kGuardOnTitle)) return true;
  if (starts_with(r.title, kGuardOffTitle)) return false;
  return std::nullopt;
}

std::optional<std::string> apply_guard_firing(const data::Reminder& r, skills::Guard* guard) {
  const std::optional<bool> on = guard_switch(r);
  if (!on) return std::nullopt;
  if (!guard) return "I can't guard the house as scheduled: I have no camera.";
  const std::string when =
      r.title.substr(*on ? std::string(kGuardOnTitle).size() : std::string(kGuardOffTitle).size());
  if (*on) {
    guard->on();
    return "Guard mode is on, as scheduled (" + when + ").";
  }
  if (!guard->state().on) return std::string();  // already off: nothing to say
  guard->off(kOffBySchedule);
  return "Guard mode is off, as scheduled (" + when + ").";
}

}  // namespace marvin::app
