#include "interpret/time_expression.h"

#include <array>
#include <initializer_list>
#include <string_view>

#include "interpret/durations.h"
#include "interpret/number_words.h"

namespace marvin::interpret {
namespace {

constexpr std::array<std::string_view, 7> kWeekdays{
    "sunday", "monday", "tuesday", "wednesday", "thursday", "friday", "saturday"};

constexpr std::array<std::string_view, 12> kMonths{
    "january", "february", "march",     "april",   "may",      "june",
    "july",    "august",   "september", "october", "november", "december"};

// "march", "mar", "sept", "sep": 1..12. "may" is a month here; the grammar asks for a day
// number next to it, so "may i ..." never reads as a date.
std::optional<int> month_of(std::string_view word) {
  for (std::size_t m = 0; m < kMonths.size(); ++m) {
    if (word == kMonths[m]) return static_cast<int>(m) + 1;
  }
  if (word == "sept") return 9;
  if (word.size() == 3) {
    for (std::size_t m = 0; m < kMonths.size(); ++m) {
      if (kMonths[m].substr(0, 3) == word) return static_cast<int>(m) + 1;
    }
  }
  return std::nullopt;
}

// "4", "4th", "21st", "22nd", "3rd": 1..31.
std::optional<int> day_number_of(std::string_view word) {
  for (std::string_view suffix : {"st", "nd", "rd", "th"}) {
    if (word.size() > suffix.size() && word.ends_with(suffix)) {
      word.remove_suffix(suffix.size());
      break;
    }
  }
  if (word.empty() || word.size() > 2) return std::nullopt;
  int n = 0;
  for (char c : word) {
    if (c < '0' || c > '9') return std::nullopt;
    n = n * 10 + (c - '0');
  }
  if (n < 1 || n > 31) return std::nullopt;
  return n;
}

constexpr unsigned kMondayToFriday = 0b0111110U;
constexpr unsigned kWeekend = 0b1000001U;

std::optional<int> weekday_of(std::string_view word, bool* plural) {
  for (std::size_t d = 0; d < kWeekdays.size(); ++d) {
    if (word == kWeekdays[d]) {
      if (plural) *plural = false;
      return static_cast<int>(d);
    }
    if (word.size() == kWeekdays[d].size() + 1 && word.substr(0, kWeekdays[d].size()) ==
                                                      kWeekdays[d] && word.back() == 's') {
      if (plural) *plural = true;
      return static_cast<int>(d);
    }
  }
  return std::nullopt;
}

// "48 hours", "90 minutes": a duration said on the clock, not in days or weeks.
bool names_clock_units(std::span<const std::string> words) {
  for (const std::string& w : words) {
    for (const char* unit : {"hour", "min", "sec"}) {  // "minutes", "mins", "seconds", ...
      if (w.rfind(unit, 0) == 0) return true;
    }
  }
  return false;
}

// Recursive-descent reader over the tokens; every read_* restores the position on failure.
class TimeReader {
 public:
  explicit TimeReader(std::span<const std::string> words) : w_(words) {}

  std::optional<TimePhrase> read() {
    TimePhrase phrase;
    if (accept("in")) {
      auto seconds = parse_duration(w_.subspan(at_));
      if (!seconds) return std::nullopt;
      // "in two days", "in a week": a day, at the day's default hour like "on Tuesday" (a
      // reminder said at 10:52 PM is not for 10:52 PM); "in 48 hours" stays to the minute.
      constexpr std::int64_t kDay = 24 * 60 * 60;
      if (*seconds >= kDay && *seconds % kDay == 0 && !names_clock_units(w_.subspan(at_))) {
        phrase.day_offset = static_cast<int>(*seconds / kDay);
        return phrase;
      }
      phrase.in_seconds = *seconds;
      return phrase;
    }
    bool have_time = false, have_day = false, have_recurrence = false, have_part = false;
    while (at_ < w_.size()) {
      std::size_t start = at_;
      // A calendar date first: "3 march" is not the hour 3.
      if (!have_day && !have_recurrence && read_calendar_date(phrase)) {
        have_day = true;
        continue;
      }
      at_ = start;
      if (!have_time) {
        accept("at");
        if (auto t = read_time_of_day()) {
          phrase.time = *t;
          have_time = true;
          continue;
        }
        at_ = start;
      }
      if (!have_day && !have_recurrence) {
        if (read_day(phrase)) {
          have_day = true;
          continue;
        }
        at_ = start;
        if (read_recurrence(phrase)) {
          have_recurrence = true;
          if (phrase.kind == RecurrenceKind::kInterval) {
            // "every 2 hours" stands alone.
            if (at_ != w_.size() || have_time) return std::nullopt;
            return phrase;
          }
          if (phrase.default_hour != 0) have_part = true;  // "every morning"
          continue;
        }
        at_ = start;
      }
      if (!have_part && !phrase.evening && read_meal_time(phrase)) {
        have_part = true;
        continue;
      }
      at_ = start;
      if (!have_part && !phrase.evening) {
        bool today = false;
        if (read_part_of_day(phrase, today)) {
          have_part = true;
          if (today) {  // "this evening" is a day too
            if (have_day || have_recurrence) return std::nullopt;
            phrase.day_offset = 0;
            have_day = true;
          }
          continue;
        }
        at_ = start;
      }
      return std::nullopt;
    }
    if (!have_time && !have_day && !have_recurrence && !have_part) return std::nullopt;
    if (have_part && phrase.range != DayRange::kNone) return std::nullopt;  // "next week morning"
    if (phrase.range != DayRange::kNone && have_time) return std::nullopt;  // "next week at 8"
    return phrase;
  }

 private:
  bool accept(std::string_view word) {
    if (at_ < w_.size() && w_[at_] == word) {
      ++at_;
      return true;
    }
    return false;
  }
  bool accept_seq(std::initializer_list<std::string_view> seq) {
    std::size_t start = at_;
    for (auto word : seq) {
      if (!accept(word)) {
        at_ = start;
        return false;
      }
    }
    return true;
  }
  std::optional<std::int64_t> read_int(std::int64_t lo, std::int64_t hi) {
    if (at_ >= w_.size()) return std::nullopt;
    auto v = parse_integer(w_[at_]);
    if (!v || *v < lo || *v > hi) return std::nullopt;
    ++at_;
    return v;
  }

  // "H", "H:MM", "H MM", "H oh M", "half past H", "quarter to H", "M [minutes] past H",
  // "noon", "midnight"; then "o'clock" and a meridiem.
  std::optional<TimeOfDay> read_time_of_day() {
    std::size_t start = at_;
    if (accept("noon") || accept("midday")) return TimeOfDay{12, 0, false};
    if (accept("midnight")) return TimeOfDay{0, 0, false};

    int hour = -1, minute = 0;
    std::optional<int> relative;  // minutes past (+) or to (-) the hour
    // "half past seven", and the British "half seven" (7:30, never 6:30).
    auto next_is_hour = [&] {
      const auto h = at_ < w_.size() ? parse_integer(w_[at_]) : std::nullopt;
      return h && *h >= 1 && *h <= 12;
    };
    if (accept("half") && (accept("past") || next_is_hour())) {
      relative = 30;
    } else {
      at_ = start;
      if ((accept_seq({"a", "quarter"}) || accept("quarter"))) {
        if (accept("past")) {
          relative = 15;
        } else if (accept("to")) {
          relative = -15;
        } else {
          at_ = start;
          return std::nullopt;
        }
      } else if (auto m = read_int(1, 30)) {
        std::size_t after_number = at_;
        (void)(accept("minutes") || accept("minute") || accept("mins") || accept("min"));
        if (accept("past")) {
          relative = static_cast<int>(*m);
        } else if (accept("to")) {
          relative = -static_cast<int>(*m);
        } else {
          at_ = after_number - 1;  // not a relative time: re-read the number as the hour
        }
      }
    }

    if (relative) {
      auto h = read_int(1, 12);
      if (!h) {
        at_ = start;
        return std::nullopt;
      }
      hour = static_cast<int>(*h);
      if (*relative >= 0) {
        minute = *relative;
      } else {
        hour = hour == 1 ? 12 : hour - 1;  // "quarter to 1" = 12:45
        minute = 60 + *relative;
      }
    } else if (at_ < w_.size()) {
      const std::string& token = w_[at_];
      std::size_t colon = token.find(':');
      if (colon != std::string::npos) {
        auto h = parse_integer(std::string_view(token).substr(0, colon));
        std::string_view mm = std::string_view(token).substr(colon + 1);
        auto m = parse_integer(mm);
        if (!h || !m || mm.size() != 2 || *h > 23 || *m > 59) {
          at_ = start;
          return std::nullopt;
        }
        hour = static_cast<int>(*h);
        minute = static_cast<int>(*m);
        ++at_;
      } else if (auto h = read_int(0, 24)) {
        hour = static_cast<int>(*h == 24 ? 0 : *h);
        std::size_t after_hour = at_;
        if (accept("oh")) {
          if (auto m = read_int(0, 9)) {
            minute = static_cast<int>(*m);
          } else {
            at_ = after_hour;
          }
        } else if (at_ < w_.size() && w_[at_].size() == 2) {
          // "7 30", "8 05": a two-digit minute right after the hour.
          if (auto m = read_int(0, 59)) minute = static_cast<int>(*m);
        }
      } else {
        at_ = start;
        return std::nullopt;
      }
    } else {
      at_ = start;
      return std::nullopt;
    }

    accept("o'clock");
    TimeOfDay time{hour, minute, false};
    enum class Meridiem { kNone, kAm, kPm, kNight } meridiem = Meridiem::kNone;
    if (accept("am") || accept_seq({"a", "m"}) || accept_seq({"in", "the", "morning"})) {
      meridiem = Meridiem::kAm;
    } else if (accept("pm") || accept_seq({"p", "m"}) ||
               accept_seq({"in", "the", "afternoon"}) ||
               accept_seq({"in", "the", "evening"}) || accept("tonight")) {
      meridiem = Meridiem::kPm;
    } else if (accept_seq({"at", "night"})) {
      meridiem = Meridiem::kNight;
    }
    if (meridiem != Meridiem::kNone) {
      if (hour < 1 || hour > 12) {
        at_ = start;
        return std::nullopt;
      }
      if (meridiem == Meridiem::kAm) {
        time.hour = hour % 12;
      } else if (meridiem == Meridiem::kPm) {
        time.hour = hour % 12 + 12;
      } else {  // night: 9..11 pm, 12 = midnight, 1..4 early morning
        time.hour = hour == 12 ? 0 : (hour <= 4 ? hour : hour + 12);
      }
    } else if (hour >= 1 && hour <= 11) {
      time.ambiguous = true;
    }
    return time;
  }

  // "morning", "in the afternoon", "this evening", "at night": which half of the clock an
  // hour without am/pm is in, and the hour meant when no time is said. `today` is set for
  // "this ...". ("at 8 in the morning" right after a time is read_time_of_day's.)
  bool read_part_of_day(TimePhrase& phrase, bool& today) {
    today = accept("this");
    if (!today) (void)(accept_seq({"in", "the"}) || accept("at"));
    struct Part {
      std::string_view word;
      bool morning;
      int hour;
    };
    static constexpr std::array<Part, 4> kParts{
        Part{"morning", true, 9}, Part{"afternoon", false, 15}, Part{"evening", false, 19},
        Part{"night", false, 21}};
    for (const Part& part : kParts) {
      if (accept(part.word)) {
        set_part(phrase, part.morning, part.hour);
        return true;
      }
    }
    return false;
  }

  // "after lunch", "with breakfast", "before dinner", "at bedtime", "before going to bed":
  // pills are taken with meals, so people tie reminders to them. The hour a household
  // usually eats at (breakfast 8, lunch 12, tea 16, dinner or supper 18, bed 21), an hour
  // earlier for "before", later for "after"; said back, so the user hears what was set.
  bool read_meal_time(TimePhrase& phrase) {
    int shift = 0;
    if (accept("after")) {
      shift = 1;
    } else if (accept("before")) {
      shift = -1;
    } else {
      (void)(accept("at") || accept("with") || accept("around") || accept("by"));
    }
    const bool article = accept("my") || accept("the") || accept("your");
    int hour = -1;
    bool bed = false;
    if (accept("breakfast") || accept("breakfasttime")) {
      hour = 8;
    } else if (accept("lunch") || accept("lunchtime") || accept("luncheon")) {
      hour = 12;
    } else if (accept("teatime") || accept_seq({"afternoon", "tea"})) {
      hour = 16;
    } else if (accept("dinner") || accept("supper") || accept("dinnertime") ||
               accept("suppertime")) {
      hour = 18;
    } else if (accept("bedtime") || (!article && accept("bed")) ||
               accept_seq({"going", "to", "bed"})) {
      // "the bed", "my bed" is the furniture ("go to the bed"); "before bed" is the time.
      hour = 21;
      bed = true;
    }
    if (hour < 0 || (bed && shift > 0)) return false;  // "after bed" is no time
    (void)accept("time");
    if (!bed) hour += shift;
    set_part(phrase, hour < 12, hour);
    return true;
  }

  static void set_part(TimePhrase& phrase, bool morning, int hour) {
    (morning ? phrase.morning : phrase.evening) = true;
    phrase.default_hour = hour;
  }

  bool read_day(TimePhrase& phrase) {
    std::size_t start = at_;
    if (accept("today")) {
      phrase.day_offset = 0;
      return true;
    }
    if (accept("tonight")) {  // today, and without a time in the evening, not at 9 AM
      phrase.day_offset = 0;
      set_part(phrase, false, 20);
      return true;
    }
    if (accept("tomorrow")) {
      phrase.day_offset = 1;
      return true;
    }
    if (accept_seq({"the", "day", "after", "tomorrow"}) ||
        accept_seq({"day", "after", "tomorrow"})) {
      phrase.day_offset = 2;
      return true;
    }
    if (read_range(phrase)) return true;
    at_ = start;
    if (read_calendar_date(phrase)) return true;
    at_ = start;
    (void)(accept("on") || accept("next") || accept("this") || accept("coming"));
    bool plural = false;
    if (at_ < w_.size()) {
      if (auto d = weekday_of(w_[at_], &plural); d && !plural) {
        ++at_;
        phrase.weekday_mask = 1U << *d;
        return true;
      }
    }
    at_ = start;
    return false;
  }

  // A day number: "4", "4th", or "20 1st" (number words normalise to two tokens).
  std::optional<int> read_day_number() {
    if (at_ >= w_.size()) return std::nullopt;
    if (at_ + 1 < w_.size() && (w_[at_] == "20" || w_[at_] == "30")) {
      auto unit = day_number_of(w_[at_ + 1]);
      if (unit && *unit <= 9 && w_[at_ + 1].size() > 1) {
        const int n = (w_[at_] == "20" ? 20 : 30) + *unit;
        if (n <= 31) {
          at_ += 2;
          return n;
        }
      }
    }
    auto n = day_number_of(w_[at_]);
    if (n) ++at_;
    return n;
  }

  // "[on] [the] march [the] 3rd [2027]", "[on] [the] 3rd [of] march [2027]".
  bool read_calendar_date(TimePhrase& phrase) {
    std::size_t start = at_;
    accept("on");
    accept("the");
    int month = 0, day = 0;
    if (read_holiday(month, day)) {
      phrase.month = month;
      phrase.day_of_month = day;
      read_year(phrase);
      return true;
    }
    if (read_easter_feast(phrase)) return true;
    if (at_ < w_.size()) {
      if (auto m = month_of(w_[at_])) {
        ++at_;
        accept("the");
        if (auto d = read_day_number()) {
          month = *m;
          day = *d;
        }
      } else if (auto d = read_day_number()) {
        accept("of");
        if (at_ < w_.size()) {
          if (auto m2 = month_of(w_[at_])) {
            ++at_;
            month = *m2;
            day = *d;
          }
        }
      }
    }
    if (month == 0) {
      at_ = start;
      return false;
    }
    phrase.month = month;
    phrase.day_of_month = day;
    read_year(phrase);
    return true;
  }

  // After a date: "2027", or "this year" (the next one, as without it).
  void read_year(TimePhrase& phrase) {
    if (accept_seq({"this", "year"})) return;
    if (at_ < w_.size() && w_[at_].size() == 4) {
      if (auto y = parse_integer(w_[at_]); y && *y >= 1900 && *y <= 2200) {
        phrase.year = static_cast<int>(*y);
        ++at_;
      }
    }
  }

  // A holiday on the same date every year: "christmas [day]", "christmas eve", "boxing day",
  // "new year's [day|eve]", "halloween", "valentine's day". (Easter moves: read_easter_feast.)
  bool read_holiday(int& month, int& day) {
    const std::size_t start = at_;
    auto found = [&](int m, int d) {
      month = m;
      day = d;
      return true;
    };
    if (accept("christmas") || accept("xmas")) {
      if (accept("eve")) return found(12, 24);
      accept("day");
      return found(12, 25);
    }
    if (accept_seq({"boxing", "day"})) return found(12, 26);
    if (accept("halloween")) return found(10, 31);
    if ((accept("valentine's") || accept("valentines") || accept_seq({"valentine", "s"})) &&
        accept("day")) {
      return found(2, 14);
    }
    at_ = start;
    if (accept("new") &&
        (accept("year's") || accept("years") || accept_seq({"year", "s"}) || accept("year"))) {
      if (accept("eve")) return found(12, 31);
      accept("day");
      return found(1, 1);
    }
    at_ = start;
    return false;
  }

  // "easter [sunday|day]", "good friday", "easter monday", "ascension day", "whit sunday",
  // "pentecost", "whit monday", "ash wednesday": the feasts that move with Easter, as days
  // from Easter Sunday (Western churches), then "[this year|2027]" as for a date.
  bool read_easter_feast(TimePhrase& phrase) {
    const std::size_t start = at_;
    std::optional<int> days;
    if (accept("easter")) {
      days = accept("monday") ? 1 : accept("saturday") ? -1 : 0;
      if (*days == 0) (void)(accept("sunday") || accept("day"));
    } else if (accept_seq({"good", "friday"})) {
      days = -2;
    } else if (accept_seq({"ash", "wednesday"})) {
      days = -46;
    } else if (accept_seq({"ascension", "day"}) || accept("ascension")) {
      days = 39;
    } else if (accept("pentecost") || accept_seq({"whit", "sunday"}) || accept("whitsun") ||
               accept("whitsunday")) {
      days = 49;
    } else if (accept_seq({"whit", "monday"})) {
      days = 50;
    }
    if (!days) {
      at_ = start;
      return false;
    }
    phrase.days_from_easter = days;
    read_year(phrase);
    return true;
  }

  // "next week", "this weekend", "over the weekend", "for the week": a span of days.
  bool read_range(TimePhrase& phrase) {
    (void)(accept("for") || accept("over") || accept("during") || accept("in"));
    bool next = false;
    if (accept("next") || accept("coming") || accept_seq({"the", "coming"})) {
      next = true;
    } else {
      (void)(accept("this") || accept("the"));
    }
    if (accept("weekend")) {
      phrase.range = next ? DayRange::kNextWeekend : DayRange::kThisWeekend;
      return true;
    }
    if (accept("week")) {
      phrase.range = next ? DayRange::kNextWeek : DayRange::kThisWeek;
      return true;
    }
    return false;
  }

  // Weekday list after "every"/"on": "monday", "monday and wednesday", "mondays".
  unsigned read_weekday_list(bool require_plural) {
    unsigned mask = 0;
    while (at_ < w_.size()) {
      bool plural = false;
      auto d = weekday_of(w_[at_], &plural);
      if (!d || (require_plural && !plural)) break;
      mask |= 1U << *d;
      ++at_;
      std::size_t before_and = at_;
      if (!accept("and")) break;
      bool next_plural = false;
      if (at_ >= w_.size() || !weekday_of(w_[at_], &next_plural)) {
        at_ = before_and;
        break;
      }
    }
    return mask;
  }

  void set_weekdays(TimePhrase& phrase, unsigned mask) {
    phrase.weekday_mask = mask;
    phrase.kind = mask == kMondayToFriday ? RecurrenceKind::kWeekdays : RecurrenceKind::kWeekly;
  }

  bool read_recurrence(TimePhrase& phrase) {
    std::size_t start = at_;
    if (accept("daily") || accept_seq({"every", "day"}) || accept_seq({"each", "day"})) {
      phrase.kind = RecurrenceKind::kDaily;
      return true;
    }
    if (accept_seq({"every", "morning"}) || accept_seq({"each", "morning"})) {
      phrase.kind = RecurrenceKind::kDaily;
      set_part(phrase, true, 9);
      return true;
    }
    if (accept_seq({"every", "evening"}) || accept_seq({"each", "evening"})) {
      phrase.kind = RecurrenceKind::kDaily;
      set_part(phrase, false, 19);
      return true;
    }
    if (accept_seq({"every", "night"}) || accept_seq({"each", "night"}) || accept("nightly")) {
      phrase.kind = RecurrenceKind::kDaily;
      set_part(phrase, false, 21);
      return true;
    }
    if (accept_seq({"every", "weekday"}) || accept_seq({"on", "weekdays"}) ||
        accept("weekdays") || accept_seq({"every", "working", "day"})) {
      set_weekdays(phrase, kMondayToFriday);
      return true;
    }
    if (accept_seq({"every", "weekend"}) || accept_seq({"on", "weekends"}) ||
        accept_seq({"at", "weekends"}) || accept_seq({"on", "the", "weekend"})) {
      set_weekdays(phrase, kWeekend);
      return true;
    }
    if (accept("every") || accept("each")) {
      std::size_t after_every = at_;
      if (unsigned mask = read_weekday_list(false)) {
        set_weekdays(phrase, mask);
        return true;
      }
      at_ = after_every;
      // Interval: "every 2 hours", "every hour", "every 30 minutes", "every half hour".
      std::optional<std::int64_t> seconds;
      if (at_ < w_.size()) {
        if (auto unit = duration_unit_seconds(w_[at_]); unit && at_ + 1 == w_.size()) {
          seconds = *unit;
          ++at_;
        } else if (accept_seq({"half", "hour"})) {
          seconds = 1800;
        } else {
          seconds = parse_duration(w_.subspan(at_));
          if (seconds) at_ = w_.size();
        }
      }
      if (seconds && *seconds >= 60) {
        phrase.kind = RecurrenceKind::kInterval;
        phrase.every_seconds = *seconds;
        return true;
      }
      at_ = start;
      return false;
    }
    accept("on");
    if (unsigned mask = read_weekday_list(true)) {
      set_weekdays(phrase, mask);
      return true;
    }
    at_ = start;
    return false;
  }

  std::span<const std::string> w_;
  std::size_t at_ = 0;
};

}  // namespace

std::optional<TimePhrase> parse_time_phrase(std::span<const std::string> words) {
  if (words.empty() || words.size() > 12) return std::nullopt;
  return TimeReader(words).read();
}

namespace {

// What day(s) a phrase names, as opposed to the time of day it names.
bool names_day(const TimePhrase& p) {
  return p.kind != RecurrenceKind::kOnce || p.day_offset || p.weekday_mask != 0 ||
         p.dated() || p.range != DayRange::kNone;
}
bool names_time_of_day(const TimePhrase& p) { return p.time || p.default_hour != 0; }
void copy_day(const TimePhrase& from, TimePhrase& to) {
  to.kind = from.kind;
  to.day_offset = from.day_offset;
  to.weekday_mask = from.weekday_mask;
  to.month = from.month;
  to.day_of_month = from.day_of_month;
  to.days_from_easter = from.days_from_easter;
  to.year = from.year;
}

}  // namespace

std::vector<TimePhrase> parse_time_phrases(std::span<const std::string> words) {
  if (auto one = parse_time_phrase(words)) return {*one};
  for (std::size_t i = 1; i + 1 < words.size(); ++i) {
    if (words[i] != "and") continue;
    std::optional<TimePhrase> a = parse_time_phrase(words.first(i));
    std::optional<TimePhrase> b = parse_time_phrase(words.subspan(i + 1));
    if (!a || !b) continue;
    // Two times of one day or one recurrence: not "in 20 minutes", "every 2 hours", a
    // week, or two days ("monday at 9 and tuesday at 10" is two requests).
    bool joinable = true;
    for (const TimePhrase* p : {&*a, &*b}) {
      joinable = joinable && !p->in_seconds && p->kind != RecurrenceKind::kInterval &&
                 p->range == DayRange::kNone && names_time_of_day(*p);
    }
    if (!joinable || (names_day(*a) && names_day(*b))) continue;
    if (names_day(*a)) copy_day(*a, *b);
    if (names_day(*b)) copy_day(*b, *a);
    // "at 8 and 8 pm": the bare hour is the other half of the day, not the same 8 PM.
    auto other_half = [](TimePhrase& bare, const TimePhrase& clear) {
      if (!bare.time || !bare.time->ambiguous || !clear.time || clear.time->ambiguous) return;
      if (clear.time->hour >= 12) {
        bare.morning = true;
      } else {
        bare.evening = true;
      }
    };
    other_half(*a, *b);
    other_half(*b, *a);
    return {*a, *b};
  }
  return {};
}

const char* weekday_name(int weekday) {
  if (weekday < 0 || weekday > 6) return "";
  return kWeekdays[static_cast<std::size_t>(weekday)].data();
}

}  // namespace marvin::interpret
