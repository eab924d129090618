// Built-in skill "time": says the time or the date, from the host's clock in the owner's
// time zone. "what time is it" -> "It's 3:05 PM."; "what day is it" -> "Today is
// Saturday, 21 November 2026."
#include <date/tz.h>

#include <chrono>
#include <marvin/skill.hpp>
#include <string>

namespace {

class TimeSkill : public marvin::Skill {
 public:
  using marvin::Skill::Skill;

  void handle(const marvin::Request& request) override {
    auto now =
        date::sys_time<std::chrono::milliseconds>{std::chrono::milliseconds{robot().now_ms()}};
    auto local = date::make_zoned(zone(), date::floor<std::chrono::minutes>(now)).get_local_time();
    if (request.intent == "time") {
      auto day = date::floor<date::days>(local);
      auto minute_of_day = std::chrono::duration_cast<std::chrono::minutes>(local - day).count();
      auto hour = minute_of_day / 60;
      auto hour12 = hour % 12 == 0 ? 12 : hour % 12;
      std::string minutes = std::to_string(minute_of_day % 60);
      if (minutes.size() < 2) minutes = "0" + minutes;
      robot().say("It's " + std::to_string(hour12) + ":" + minutes + (hour < 12 ? " AM." : " PM."));
    } else if (request.intent == "day") {
      auto day = date::floor<date::days>(local);
      date::year_month_day ymd{day};
      robot().say("Today is " + date::format("%A", date::weekday{day}) + ", " +
                  std::to_string(static_cast<unsigned>(ymd.day())) + " " +
                  date::format("%B %Y", ymd) + ".");
    } else {
      throw marvin::Error(MARVIN_ERR_INVALID, "unknown intent '" + request.intent + "'");
    }
  }

 private:
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
