// Built-in skill "time": says the time or the date, from the host's clock in the owner's
// time zone. "what time is it" -> "It's 3:05 PM."; "what day is it" -> "Today is
// Saturday, 21 November 2026."; "what's the date tomorrow" -> "Tomorrow is Sunday, ...". With a
// place ("what time is it in new york"), the time there when the tz database names a zone after it
// ("America/New_York"); otherwise the local time and a word that the place is unknown.
// "is it morning or evening?" / "is it night?" -> "It's the evening: 7:10 PM." (someone who
// has slept in the day may not know, and "evening" alone says more than the clock).
// "is it the weekend?" / "is today Sunday?" -> "Yes, today is Saturday, ..." or "No, ...".
// "how many days until christmas?" -> "It's 26 days until Friday, 25 December."
// "what time will it be in two hours?" -> "In 2 hours it will be 6:30 PM."
// "what year is it?" -> "It's 2026."
#include <date/tz.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <marvin/skill.hpp>
#include <optional>
#include <string>
#include <vector>

#include "common/spoken_text.h"

namespace {

class TimeSkill : public marvin::Skill {
 public:
  using marvin::Skill::Skill;

  void handle(const marvin::Request& request) override {
    auto now =
        date::sys_time<std::chrono::milliseconds>{std::chrono::milliseconds{robot().now_ms()}};
    auto local = date::make_zoned(zone(), date::floor<std::chrono::minutes>(now)).get_local_time();
    if (request.intent == "time") {
      const std::string place = request.slots.value("place", std::string());
      if (auto after = request.slots.find("after"); after != request.slots.end() &&
                                                     after->is_number_integer()) {
        // "what time will it be in two hours": the clock then, to the minute.
        const auto then = local + std::chrono::seconds{after->get<std::int64_t>()};
        robot().say("In " + spoken_minutes(after->get<std::int64_t>() / 60) + " it will be " +
                    clock_text(date::floor<std::chrono::minutes>(then)) +
                    (date::floor<date::days>(then) != date::floor<date::days>(local)
                         ? " tomorrow."
                         : "."));
        return;
      }
      if (place.empty()) {
        const std::string part = asks_part_of_day(request.utterance) ? part_of_day(local) : "";
        robot().say("It's " + (part.empty() ? "" : part + ": ") + clock_text(local) + ".");
        return;
      }
      if (const date::time_zone* there = zone_named_after(place)) {
        auto there_local =
            date::make_zoned(there, date::floor<std::chrono::minutes>(now)).get_local_time();
        robot().say("In " + title_case(there->name().substr(there->name().rfind('/') + 1)) +
                    " it's " + clock_text(there_local) + ".");
      } else {
        robot().say("I don't know the time zone of " + title_case(place) + ". Here it's " +
                    clock_text(local) + ".");
      }
    } else if (request.intent == "day") {
      const date::local_days today = date::floor<date::days>(local);
      date::local_days day = today;
      if (request.slots.contains("when")) {  // "what's the date tomorrow"
        if (auto asked = local_day(request.slots["when"].value("at", std::string()))) day = *asked;
      }
      const date::year_month_day ymd{day};
      // "what year is it?" / "what month is it?": that alone.
      const std::vector<std::string> asked = marvin::builtin::words_in(request.utterance);
      const bool year = std::find(asked.begin(), asked.end(), "year") != asked.end();
      if (day == today && (year || std::find(asked.begin(), asked.end(), "month") != asked.end())) {
        robot().say("It's " + date::format(year ? "%Y" : "%B %Y", ymd) + ".");
        return;
      }
      std::string which = day == today                   ? "Today is "
                          : day == today + date::days{1} ? "Tomorrow is "
                                                         : "That is ";
      if (const std::string answer = yes_or_no(request.utterance, date::weekday{day});
          day == today && !answer.empty()) {
        which = answer + "today is ";
      }
      robot().say(which + date::format("%A", date::weekday{day}) + ", " +
                  std::to_string(static_cast<unsigned>(ymd.day())) + " " +
                  date::format("%B %Y", ymd) + ".");
    } else if (request.intent == "days_until") {
      days_until(request.slots.at("when"), local);
    } else {
      throw marvin::Error(MARVIN_ERR_INVALID, "unknown intent '" + request.intent + "'");
    }
  }

 private:
  // The day of a datetime slot's local "at" ("2026-11-29T09:00"); nullopt if malformed.
  static std::optional<date::local_days> local_day(const std::string& at) {
    auto number = [&](std::size_t from, std::size_t length) {
      int n = 0;
      for (std::size_t i = from; i < from + length && i < at.size(); ++i) {
        if (!std::isdigit(static_cast<unsigned char>(at[i]))) return -1;
        n = n * 10 + (at[i] - '0');
      }
      return at.size() < from + length ? -1 : n;
    };
    const int y = number(0, 4), m = number(5, 2), d = number(8, 2);
    if (y < 0 || m < 0 || d < 0) return std::nullopt;
    const date::year_month_day ymd{date::year{y}, date::month{static_cast<unsigned>(m)},
                                   date::day{static_cast<unsigned>(d)}};
    if (!ymd.ok()) return std::nullopt;
    return date::local_days{ymd};
  }

  // "how many days until christmas" -> "It's 26 days until Friday, 25 December."; a time
  // of day only ("how long until 5 pm") -> "It's 2 hours and 5 minutes until 5 PM."
  void days_until(const nlohmann::json& when, date::local_seconds now) {
    const std::string at = when.value("at", std::string());
    const std::optional<date::local_days> day = local_day(at);
    if (!day) throw marvin::Error(MARVIN_ERR_INVALID, "slot 'when' has no date in 'at': " + at);
    const date::local_days today = date::floor<date::days>(now);
    const date::year_month_day ymd{*day};
    std::string date_text = date::format("%A", date::weekday{*day}) + ", " +
                            std::to_string(static_cast<unsigned>(ymd.day())) + " " +
                            date::format("%B", ymd);
    if (ymd.year() != date::year_month_day{today}.year()) date_text += date::format(" %Y", ymd);
    const auto days = (*day - today).count();
    if (when.value("time_given", false) && !when.value("day_given", false) && at.size() >= 16) {
      const int hour = std::stoi(at.substr(11, 2)), minute = std::stoi(at.substr(14, 2));
      const date::local_seconds target =
          *day + std::chrono::hours{hour} + std::chrono::minutes{minute};
      const auto minutes = std::chrono::duration_cast<std::chrono::minutes>(target - now).count();
      // The hour as it was asked: "until midnight", "until 5 PM" (not "12:00 AM", "5:00 PM").
      std::string until = clock_text(target);
      if (minute == 0) {
        const std::string twelve = std::to_string(hour % 12 == 0 ? 12 : hour % 12);
        until = hour == 0    ? "midnight"
                : hour == 12 ? "noon"
                             : twelve + (hour < 12 ? " AM" : " PM");
      }
      robot().say("It's " + spoken_minutes(minutes) + " until " + until +
                  (days > 0 && hour != 0 ? " tomorrow." : "."));
      return;
    }
    if (days == 0) return robot().say("That's today, " + date_text + ".");
    if (days == 1) return robot().say("That's tomorrow, " + date_text + ".");
    robot().say("It's " + std::to_string(days) + " days until " + date_text + ".");
  }

  // 125 -> "2 hours and 5 minutes"; 60 -> "1 hour"; 0 -> "less than a minute".
  static std::string spoken_minutes(long long minutes) {
    auto unit = [](long long n, const char* name) {
      return std::to_string(n) + " " + name + (n == 1 ? "" : "s");
    };
    if (minutes <= 0) return "less than a minute";
    const long long h = minutes / 60, m = minutes % 60;
    if (h == 0) return unit(m, "minute");
    if (m == 0) return unit(h, "hour");
    return unit(h, "hour") + " and " + unit(m, "minute");
  }

  // "is it Sunday?", "is today the weekend?": "Yes, " or "No, " before the date; "" for a
  // request that asks no such question.
  static std::string yes_or_no(const std::string& utterance, date::weekday today) {
    const std::vector<std::string> words = marvin::builtin::words_in(utterance);
    if (words.empty() || words[0] != "is") return "";
    const bool weekend = today == date::Saturday || today == date::Sunday;
    for (const std::string& w : words) {
      if (w == "weekend") return weekend ? "Yes, " : "No, ";
      if (w == "weekday") return weekend ? "No, " : "Yes, ";
      for (unsigned d = 0; d < 7; ++d) {
        if (w == marvin::builtin::lower(date::format("%A", date::weekday{d}))) {
          return date::weekday{d} == today ? "Yes, " : "No, ";
        }
      }
    }
    return "";
  }

  // "is it morning", "day or night", "what part of the day is it".
  static bool asks_part_of_day(const std::string& utterance) {
    for (const std::string& word : marvin::builtin::words_in(utterance)) {
      for (const char* part : {"morning", "afternoon", "evening", "night", "nighttime",
                               "daytime", "day"}) {
        if (word == part) return true;
      }
    }
    return false;
  }

  // Morning 5-12, afternoon 12-18, evening 18-22, night 22-5.
  static std::string part_of_day(date::local_seconds local) {
    const auto hour = std::chrono::duration_cast<std::chrono::hours>(
                          local - date::floor<date::days>(local))
                          .count();
    if (hour >= 5 && hour < 12) return "the morning";
    if (hour >= 12 && hour < 18) return "the afternoon";
    if (hour >= 18 && hour < 22) return "the evening";
    return "night";
  }

  static std::string clock_text(date::local_seconds local) {
    auto day = date::floor<date::days>(local);
    auto minute_of_day = std::chrono::duration_cast<std::chrono::minutes>(local - day).count();
    auto hour = minute_of_day / 60;
    auto hour12 = hour % 12 == 0 ? 12 : hour % 12;
    std::string minutes = std::to_string(minute_of_day % 60);
    if (minutes.size() < 2) minutes = "0" + minutes;
    return std::to_string(hour12) + ":" + minutes + (hour < 12 ? " AM" : " PM");
  }

  // "new york" -> "New York"; "New_York" -> "New York".
  static std::string title_case(std::string text) {
    bool start = true;
    for (char& c : text) {
      if (c == '_') c = ' ';  // zone names: "New_York"
      if (start) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
      start = c == ' ';
    }
    return text;
  }

  // The zone whose city part is the place ("America/New_York" for "new york", "Europe/London"
  // for "london", "America/Mexico_City" for "mexico"), compared without case, "_" read as a
  // space; nullptr when none is. Countries are not looked up (the tz database names cities).
  static const date::time_zone* zone_named_after(std::string place) {
    for (const char* article : {"the "}) {
      if (place.rfind(article, 0) == 0) place.erase(0, std::string(article).size());
    }
    // "in new york right now": words about now are no part of the place.
    for (const char* tail : {" right now", " now", " today", " at the moment"}) {
      const std::string t = tail;
      if (place.size() > t.size() && place.compare(place.size() - t.size(), t.size(), t) == 0) {
        place.erase(place.size() - t.size());
        break;
      }
    }
    if (place.empty()) return nullptr;
    for (const date::time_zone& z : date::get_tzdb().zones) {
      const std::string& name = z.name();
      const auto slash = name.rfind('/');
      if (slash == std::string::npos) continue;  // "UTC", "EST": no city
      std::string city = name.substr(slash + 1);
      for (char& c : city) {
        c = c == '_' ? ' ' : static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
      }
      if (city == place || city == place + " city") return &z;  // "mexico" -> Mexico_City
    }
    return nullptr;
  }

  const date::time_zone* zone() {
    std::string name = robot().time_zone();
    try {
      return date::locate_zone(name);
    } catch (const std::exception&) {
      robot().log(MARVIN_LOG_WARNING, "unknown time zone '" + name + "', using UTC");
      return date::locate_zone("UTC");
    }
  }
};

}  // namespace

MARVIN_SKILL(TimeSkill, "time")
