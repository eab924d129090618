// Built-in skill "schedule": reminders and contacts by voice.
//   "remind me to take my pills at 8 pm"           -> a one-off reminder
//   "remind me every day at 9 to water the plants" -> a recurring one
//   "what's on my schedule tomorrow"               -> that day's reminders, recurring included
//   "when is my dentist appointment"               -> "Dentist appointment: on Friday, ..."
//   "cancel the pill reminder"                     -> cancels the one reminder that matches
//   "move my dentist appointment to Thursday"      -> the same time on the new day (or the
//                                                     new time, on its day, for "to 3 pm")
//   "delete all my reminders"                      -> asks, then cancels every reminder
//   "add a contact"                                -> asks name and number
//   "what is Anna's number"
//   "who are my contacts"                          -> their names, the relation first
//   "delete Peter from my contacts"                -> asks, then forgets that contact
//   "snooze" / "remind me again in 20 minutes" -> the reminder that fired last fires again
//                                                 then (10 minutes when no time is said)
//   "done" / "I took them"                     -> marks the reminder that fired last done
//   "did I take my pills?"                     -> from the event log: what was marked done
//                                                 today, and when
// Every acknowledgement is spoken only after the Robot API call returned, and the host
// returns from schedule_add / contacts_add / schedule_remove only once the change is
// committed durably (core/data): "OK" always means stored.
#include <algorithm>
#include <cctype>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <date/date.h>
#include <date/tz.h>
#include <marvin/skill.hpp>

#include "common/spoken_text.h"

namespace {

using marvin::builtin::capital;
using marvin::builtin::capitalised;
using marvin::builtin::join_and;
using marvin::builtin::lower;
using marvin::builtin::said_yes;
using marvin::builtin::words_in;

using nlohmann::json;

constexpr const char* kWeekdayNames[] = {"monday", "tuesday", "wednesday", "thursday",
                                         "friday", "saturday", "sunday"};

std::vector<std::string> words_of(const std::string& text) {
  std::vector<std::string> out;
  std::string word;
  for (char c : text + " ") {
    if (c == ' ') {
      if (!word.empty()) out.push_back(word);
      word.clear();
    } else {
      word += c;
    }
  }
  return out;
}

// "Tom's" -> "Tom": the owner of a possessive.
std::string without_possessive(std::string word) {
  if (word.size() > 2 && word.compare(word.size() - 2, 2, "'s") == 0) word.resize(word.size() - 2);
  return word;
}

// "take my pills" said by the owner is "take your pills" said back.
std::string second_person(const std::string& text) {
  std::string out;
  for (const std::string& w : words_of(text)) {
    std::string t = w;
    if (w == "my" || w == "our") t = "your";
    else if (w == "me" || w == "i") t = "you";
    else if (w == "myself") t = "yourself";
    else if (w == "i'm") t = "you're";
    else if (w == "mine") t = "yours";
    if (!out.empty()) out += ' ';
    out += t;
  }
  return out;
}

// What a cancelled reminder was: "the reminder to take your pills"; an event on the calendar
// ("a dentist appointment", "my appointment with the bank") by its name: "the dentist
// appointment", "your appointment with the bank".
std::string cancelled(const std::string& title) {
  const std::string t = lower(title);
  for (const char* article : {"a ", "an ", "the "}) {
    if (t.rfind(article, 0) == 0) return "the " + second_person(title.substr(std::strlen(article)));
  }
  if (t.rfind("my ", 0) == 0 || t.find("appointment") != std::string::npos) {
    return second_person(title);
  }
  return "the reminder to " + second_person(title);
}

// "my dentist appointment", "the next bus" -> "your dentist appointment", "your next bus":
// what the user asked about, said back as theirs (never "your the next bus").
std::string yours(const std::string& task) {
  std::string what = lower(task);
  for (const char* lead : {"the ", "my ", "your ", "our "}) {
    if (what.rfind(lead, 0) == 0) {
      what = what.substr(std::string(lead).size());
      break;
    }
  }
  return "your " + second_person(what);
}

// "0171 5550101" -> "0 1 7 1, 5 5 5 0 1 0 1": digits one by one, groups kept, for speech.
std::string spoken_number(const std::string& number) {
  std::string out;
  for (char c : number) {
    if (std::isdigit(static_cast<unsigned char>(c))) {
      if (!out.empty() && out.back() != ' ') out += ' ';
      out += c;
    } else if (c == '+') {
      out += "plus ";
    } else if (c == ' ' && !out.empty() && out.back() != ',') {
      out += ',';
    }
  }
  return out;
}

struct LocalTime {
  date::local_days day;
  int minute_of_day = 0;
};

// "YYYY-MM-DDTHH:MM" -> day and minute; throws if malformed (a host bug, not the user's).
LocalTime parse_local(const std::string& text) {
  int y = 0, mo = 0, d = 0, h = 0, mi = 0;
  if (std::sscanf(text.c_str(), "%d-%d-%dT%d:%d", &y, &mo, &d, &h, &mi) != 5)
    throw std::runtime_error("unexpected local time '" + text + "' from the host");
  const auto ymd = date::year{y} / date::month{static_cast<unsigned>(mo)} /
                   date::day{static_cast<unsigned>(d)};
  return {date::local_days{ymd}, h * 60 + mi};
}

// 20:00 -> "8 PM", 07:30 -> "7:30 AM".
std::string spoken_time(int minute_of_day) {
  const int hour = minute_of_day / 60, minute = minute_of_day % 60;
  const int hour12 = hour % 12 == 0 ? 12 : hour % 12;
  std::string out = std::to_string(hour12);
  if (minute != 0) out += (minute < 10 ? ":0" : ":") + std::to_string(minute);
  return out + (hour < 12 ? " AM" : " PM");
}

unsigned monday_based(date::local_days day) { return (date::weekday{day}.c_encoding() + 6) % 7; }

// "today", "tomorrow" or "on Monday, 7 December".
std::string spoken_day(date::local_days day, date::local_days today) {
  if (day == today) return "today";
  if (day == today + date::days{1}) return "tomorrow";
  const date::year_month_day ymd{day};
  return "on " + capital(kWeekdayNames[monday_based(day)]) + ", " +
         std::to_string(static_cast<unsigned>(ymd.day())) + " " + date::format("%B", ymd.month());
}

std::vector<std::string> weekdays_of(const json& recurrence) {
  std::vector<std::string> out;
  if (auto it = recurrence.find("weekdays"); it != recurrence.end() && it->is_array())
    for (const json& d : *it) out.push_back(d.get<std::string>());
  return out;
}

// "every day at 9 AM", "every weekday at 7:30 AM", "every Monday and Thursday at 10 AM",
// "every 2 hours", or "" for a one-off reminder.
std::string spoken_recurrence(const json& recurrence, int minute_of_day) {
  const std::string kind = recurrence.value("kind", "once");
  const std::string at = " at " + spoken_time(minute_of_day);
  if (kind == "daily") return "every day" + at;
  if (kind == "weekdays") return "every weekday" + at;
  if (kind == "weekly") {
    std::vector<std::string> days;
    for (const std::string& d : weekdays_of(recurrence)) days.push_back(capital(d));
    return "every " + join_and(days) + at;
  }
  if (kind == "interval") {
    std::int64_t minutes = recurrence.value("every_minutes", std::int64_t{0});
    if (minutes == 0) minutes = recurrence.value("every_seconds", std::int64_t{0}) / 60;
    if (minutes % 60 == 0)
      return minutes == 60 ? "every hour" : "every " + std::to_string(minutes / 60) + " hours";
    return "every " + std::to_string(minutes) + " minutes";
  }
  return "";
}

class ScheduleSkill : public marvin::Skill {
 public:
  using marvin::Skill::Skill;

  void handle(const marvin::Request& request) override {
    if (request.intent == "remind") return remind(request);
    if (request.intent == "agenda") {
      const json& when = request.slots.at("when");
      const date::local_days first = parse_local(when.at("at")).day;
      if (when.value("days", 1) > 1) return agenda_range(first, when.at("days").get<int>());
      return agenda(first);
    }
    if (request.intent == "agenda_today") return agenda(today());
    if (request.intent == "when_is") return when_is(request.slots.at("task").get<std::string>());
    if (request.intent == "how_long") {
      return when_is(request.slots.at("task").get<std::string>(), /*how_long=*/true);
    }
    if (request.intent == "cancel") {
      // "Turn off the alarm": the alarm is the reminder; otherwise ask which.
      std::string task = request.slots.value("task", std::string());
      // "cancel a reminder" may come with the task "a reminder", which names none.
      if (lower(task) == "a reminder" || lower(task) == "reminder") task.clear();
      if (task.empty() && is_alarm(request.utterance)) task = "alarm";
      if (task.empty()) task = task_answer(robot().ask("Which reminder should I cancel?"));
      if (task.empty()) {
        return robot().say("Sorry, I didn't get which. I left your reminders as they are.");
      }
      return cancel(task);
    }
    if (request.intent == "move") return move(request);
    if (request.intent == "snooze") return snooze(request);
    if (request.intent == "done") return done(request.utterance);
    if (request.intent == "was_done") return was_done(request);
    if (request.intent == "add_contact") return add_contact(request);
    if (request.intent == "contact_number") return contact_number(request.slots.at("name").get<std::string>());
    if (request.intent == "list_contacts") return list_contacts();
    if (request.intent == "remove_contact") {
      return remove_contact(request.slots.at("name").get<std::string>());
    }
    if (request.intent == "add_event") return remind(request, true);
    if (request.intent == "have_event") return have_event(request);
    if (request.intent == "list_reminders") return list_reminders();
    if (request.intent == "set_timer") return set_timer(request.slots.at("duration").get<std::int64_t>());
    if (request.intent == "timer_left") return timer_left();
    if (request.intent == "cancel_timer") return cancel_timer();
    throw marvin::Error(MARVIN_ERR_INVALID, "unknown intent '" + request.intent + "'");
  }

 private:
  date::local_days today() {
    const auto now = date::sys_time<std::chrono::milliseconds>{std::chrono::milliseconds{robot().now_ms()}};
    const date::time_zone* zone = date::locate_zone(robot().time_zone());
    return date::floor<date::days>(zone->to_local(now));
  }

  // The task is optional in skill.json so that an alarm ("wake me at 6", "set an alarm for 7")
  // is not asked "what should I remind you of?"; any other reminder without one is asked here.
  // `event`: "add the dentist to my calendar" is said back as an entry, not as a task.
  void remind(const marvin::Request& request, bool event = false) {
    const json& when = request.slots.at("when");
    if (!request.slots.contains("task") && is_alarm(request.utterance)) {
      robot().say("OK, I'll wake you " + spoken_whens(add_reminders(kAlarmTitle, when)) + ".");
      return;
    }
    std::string task;
    if (request.slots.contains("task")) {
      task = request.slots.at("task").get<std::string>();
    } else {
      task = task_answer(robot().ask("What should I remind you of?"));
      if (task.empty()) {
        robot().say("Sorry, I didn't get what to remind you of. Let's leave it for now.");
        return;
      }
    }
    // "I need to take my pills at 9" comes as the task "need to take my pills"; "add a
    // dentist appointment on Friday" (understood by the model, no template) as "add a dentist
    // appointment": the event is the appointment.
    for (const char* lead : {"need to ", "have to ", "got to ", "must "}) {
      const std::size_t n = std::strlen(lead);
      if (task.rfind(lead, 0) == 0 && task.size() > n) task.erase(0, n);
    }
    if (event && lower(task).rfind("add ", 0) == 0 && task.size() > 4) task.erase(0, 4);
    task = with_names(task, request.utterance);
    const std::string spoken = spoken_whens(add_reminders(task, when));
    if (event) {
      robot().say("OK, I put " + second_person(task) + " on your calendar " + spoken + ".");
      return;
    }
    // "don't let me forget the bins": a thing, not a thing to do.
    static const std::set<std::string> kThingFirst = {"the", "my", "a", "an", "our", "his",
                                                      "her", "their", "your"};
    const std::vector<std::string> first = words_of(lower(task));
    const bool thing = !first.empty() && kThingFirst.count(first[0]) > 0;
    robot().say(std::string("OK, I'll remind you ") + (thing ? "about " : "to ") +
                second_person(task) + " " + spoken + ".");
  }

  // "I have a doctor's appointment on Tuesday at 10:30", "my daughter is coming on Friday":
  // said as news, not as an order, and put on the calendar as the entry it names. The entry's
  // title is built from the pieces the templates take apart: the kind ("appointment"), what
  // or whom it is with (before the kind, "doctor's appointment", or after "with", "meeting
  // with the bank"), or the visitor ("my daughter's visit").
  void have_event(const marvin::Request& request) {
    const auto slot = [&](const char* name) {
      return request.slots.contains(name) ? request.slots.at(name).get<std::string>() : std::string();
    };
    const std::string kind = slot("kind"), task = slot("task"), visitor = slot("visitor");
    if (kind.empty() && (task == "nothing" || task == "no plans" || task == "nothing on")) {
      // "I have nothing on Tuesday": a day they think is free; say whether it is.
      return agenda(parse_local(request.slots.at("when").at("at")).day);
    }
    std::string title;
    if (!visitor.empty()) {
      title = visitor + (visitor.back() == 's' ? "' visit" : "'s visit");
    } else if (task.empty()) {
      title = kind;
    } else if (kind.empty()) {
      title = task;
    } else {
      // The order they were said in: "a dentist appointment", or "an appointment with the
      // dentist" / "at the hospital" (the word before the task is its preposition).
      const std::string said = lower(request.utterance);
      const std::size_t at_task = said.find(task), at_kind = said.find(kind);
      title = task + " " + kind;
      if (at_task != std::string::npos && at_kind != std::string::npos && at_kind < at_task) {
        const std::vector<std::string> before = words_of(said.substr(0, at_task));
        const bool at = !before.empty() && before.back() == "at";
        title = kind + (at ? " at " : " with ") + task;
      }
    }
    const json created = add_reminder(title, request.slots.at("when"));
    // A kind is a thing one has one of ("a doctor's appointment"), except meals ("lunch with
    // Anna"); a visitor's title has its own possessive, a bare task ("physio") none.
    std::string spoken = second_person(title);
    if (!kind.empty() && visitor.empty() && kind != "lunch" && kind != "dinner") {
      spoken = (std::string_view("aeiou").find(spoken.front()) != std::string_view::npos ? "an " : "a ") +
               spoken;
    }
    robot().say("OK, I put " + spoken + " on your calendar " + spoken_when(created) + ".");
  }

  static constexpr const char* kAlarmTitle = "time to wake up";

  static bool is_alarm(const std::string& utterance) {
    for (const std::string& w : words_of(utterance)) {
      if (w == "wake" || w == "alarm" || w == "alarms") return true;
    }
    return false;
  }

  // "To call the bank." -> "call the bank": an answer as a task, as the interpreter hands a
  // task slot (lower case, no leading "to"/"about"/"of", no end punctuation).
  static std::string task_answer(const std::string& answer) {
    std::vector<std::string> words = words_of(lower(answer));
    std::size_t first = 0;
    while (first < words.size() &&
           (words[first] == "to" || words[first] == "about" || words[first] == "of")) {
      ++first;
    }
    std::string task;
    for (std::size_t i = first; i < words.size(); ++i) task += (task.empty() ? "" : " ") + words[i];
    while (!task.empty() && std::string_view(".!?,").find(task.back()) != std::string_view::npos) {
      task.pop_back();
    }
    return task;
  }

  // "call tom" -> "call Tom": a slot's words come in lower case. A word the user wrote
  // with a capital (not the sentence's first, not "I") keeps it, and a contact's name is
  // spelled as in the address book, for speech, which has no capitals ("doctor brown" ->
  // "Doctor Brown"; a title alone, "the doctor", stays as said).
  std::string with_names(const std::string& task, const std::string& utterance) {
    std::vector<std::string> words = words_of(task);
    auto strip = [](std::string w) {
      while (!w.empty() && std::string_view(".,!?;:\"").find(w.back()) != std::string_view::npos)
        w.pop_back();
      while (!w.empty() && std::string_view("\"(").find(w.front()) != std::string_view::npos)
        w.erase(0, 1);
      return w;
    };
    std::vector<std::vector<std::string>> names;  // as in the address book
    try {
      for (const json& c : robot().contacts_list()) {
        names.push_back(words_of(c.value("name", "")));
        for (const json& a : c.value("aliases", json::array())) {
          if (a.is_string()) names.push_back(words_of(a.get<std::string>()));
        }
      }
    } catch (const marvin::Error&) {
      // No address book to read (an older host, no permission): the user's capitals only.
    }
    static const std::set<std::string> kTitles = {"doctor", "dr", "mr", "mrs", "ms", "miss",
                                                  "nurse", "sister", "father", "mother"};
    for (const std::vector<std::string>& name : names) {
      for (std::size_t i = 0; !name.empty() && i + name.size() <= words.size(); ++i) {
        bool same = true;
        for (std::size_t k = 0; k < name.size() && same; ++k) same = lower(name[k]) == words[i + k];
        if (same) std::copy(name.begin(), name.end(), words.begin() + static_cast<std::ptrdiff_t>(i));
      }
    }
    std::map<std::string, std::string> spelled;  // lower case -> as written
    for (const std::vector<std::string>& name : names) {
      for (const std::string& w : name) {
        if (!w.empty() && std::isupper(static_cast<unsigned char>(w[0])) && !kTitles.count(lower(w)))
          spelled.emplace(lower(w), w);
      }
    }
    const std::vector<std::string> said = words_of(utterance);
    for (std::size_t i = 1; i < said.size(); ++i) {
      const std::string w = strip(said[i]);
      if (w.empty() || !std::isupper(static_cast<unsigned char>(w[0])) || w == "I" ||
          w.rfind("I'", 0) == 0) {
        continue;
      }
      spelled[lower(w)] = w;
    }
    std::string out;
    for (const std::string& w : words) {
      auto it = spelled.find(w);
      out += (out.empty() ? "" : " ") + (it != spelled.end() ? it->second : w);
    }
    return out;
  }

  // Returns once the reminder is durably stored; only then may the skill say OK.
  json add_reminder(const std::string& title, const json& when) {
    json reminder = {{"title", title}, {"at", when.at("at")}};
    if (when.contains("time_zone")) reminder["time_zone"] = when["time_zone"];
    if (when.contains("recurrence")) reminder["recurrence"] = when["recurrence"];
    return robot().schedule_add(reminder);
  }

  // One reminder per time of a datetime slot: "every day at 9 am and 9 pm" is two, the
  // second in the slot's "also".
  std::vector<json> add_reminders(const std::string& title, const json& when) {
    std::vector<json> created{add_reminder(title, when)};
    for (const json& also : when.value("also", json::array())) {
      created.push_back(add_reminder(title, also));
    }
    return created;
  }

  // "every day at 9 AM and 9 PM" (what the two share said once), "today at 9 PM and
  // tomorrow at 8 AM".
  std::string spoken_whens(std::vector<json> created) {
    // Soonest first; repeating ones by the time of day ("9 AM and 9 PM" said at noon).
    auto key = [](const json& r) {
      const std::string at = r.value("at", "");
      const bool once = r.value("recurrence", json::object()).value("kind", "once") == "once";
      return once || at.size() < 11 ? at : at.substr(11);
    };
    std::stable_sort(created.begin(), created.end(),
                     [&](const json& a, const json& b) { return key(a) < key(b); });
    std::string first = spoken_when(created.at(0));
    for (std::size_t i = 1; i < created.size(); ++i) {
      const std::string next = spoken_when(created[i]);
      const std::size_t at = first.rfind(" at ");
      if (at != std::string::npos && next.compare(0, at + 4, first, 0, at + 4) == 0) {
        first += " and " + next.substr(at + 4);
      } else {
        first += " and " + next;
      }
    }
    return first;
  }

  // "tomorrow at 6 AM", "every day at 8 AM", "every 2 hours, starting today at 3 PM".
  std::string spoken_when(const json& created) {
    const LocalTime at = parse_local(created.at("at").get<std::string>());
    const json recurrence = created.value("recurrence", json::object());
    std::string when_text = spoken_recurrence(recurrence, at.minute_of_day);
    if (when_text.empty() || recurrence.value("kind", "once") == "interval") {
      const std::string first = spoken_day(at.day, today()) + " at " + spoken_time(at.minute_of_day);
      when_text = when_text.empty() ? first : when_text + ", starting " + first;
    }
    return when_text;
  }

  // Timers are reminders titled "timer ..." (durable like them: they survive a restart and
  // fire through the same scheduler), set to the second with "utc_ms".
  static constexpr const char* kTimerTitle = "your timer is done";

  static std::string spoken_duration(std::int64_t seconds) {
    std::vector<std::string> parts;
    const std::int64_t h = seconds / 3600, m = seconds % 3600 / 60, s = seconds % 60;
    auto part = [&](std::int64_t n, const char* unit) {
      if (n > 0) parts.push_back(std::to_string(n) + " " + unit + (n == 1 ? "" : "s"));
    };
    part(h, "hour");
    part(m, "minute");
    part(s, "second");
    return parts.empty() ? "less than a second" : join_and(parts);
  }

  std::vector<json> running_timers() {
    const std::int64_t now = robot().now_ms();
    std::vector<json> timers;
    for (const json& r : robot().schedule_list(now, std::numeric_limits<std::int64_t>::max())) {
      if (r.value("title", "") == kTimerTitle) timers.push_back(r);
    }
    std::stable_sort(timers.begin(), timers.end(), [](const json& a, const json& b) {
      return a.value("next_fire_utc_ms", std::int64_t{0}) < b.value("next_fire_utc_ms", std::int64_t{0});
    });
    return timers;
  }

  void set_timer(std::int64_t seconds) {
    if (seconds <= 0 || seconds > 24 * 3600) {
      robot().say("Sorry, I can set a timer from one second up to 24 hours.");
      return;
    }
    const std::int64_t fire_ms = robot().now_ms() + seconds * 1000;
    robot().schedule_add(
        {{"title", kTimerTitle}, {"at", local_minute(fire_ms)}, {"utc_ms", fire_ms}});
    robot().say("OK, timer set for " + spoken_duration(seconds) + ".");
  }

  void timer_left() {
    const std::vector<json> timers = running_timers();
    if (timers.empty()) {
      robot().say("You have no timer running.");
      return;
    }
    const std::int64_t left_ms =
        timers.front().value("next_fire_utc_ms", std::int64_t{0}) - robot().now_ms();
    robot().say(capital(spoken_duration((left_ms + 999) / 1000)) + " left on your timer" +
                (timers.size() > 1 ? " (and " + std::to_string(timers.size() - 1) + " more)." : "."));
  }

  void cancel_timer() {
    const std::vector<json> timers = running_timers();
    if (timers.empty()) {
      robot().say("You have no timer running.");
      return;
    }
    for (const json& t : timers) robot().schedule_remove(t.at("id").get<std::int64_t>());
    robot().say(timers.size() == 1 ? "OK, I cancelled the timer."
                                   : "OK, I cancelled all " + std::to_string(timers.size()) + " timers.");
  }

  // Upcoming reminders, soonest first (at most five named).
  void list_reminders() {
    const std::int64_t now = robot().now_ms();
    std::vector<json> all;
    for (const json& r : robot().schedule_list(now, std::numeric_limits<std::int64_t>::max())) {
      if (r.value("title", "") != kTimerTitle) all.push_back(r);
    }
    std::stable_sort(all.begin(), all.end(), [](const json& a, const json& b) {
      return a.value("next_fire_utc_ms", std::int64_t{0}) < b.value("next_fire_utc_ms", std::int64_t{0});
    });
    if (all.empty()) {
      robot().say("You have no reminders set.");
      return;
    }
    std::vector<std::string> texts;
    for (std::size_t i = 0; i < all.size() && i < 5; ++i) {
      // A repeating one as it repeats ("every day at 8 AM"), not as its next time only.
      const LocalTime at = parse_local(all[i].at("at").get<std::string>());
      const json recurrence = all[i].value("recurrence", json::object());
      const std::string title = second_person(all[i].value("title", ""));
      texts.push_back(recurrence.value("kind", "once") != "once"
                          ? title + " " + spoken_recurrence(recurrence, at.minute_of_day)
                          : title + " " + spoken_day(at.day, today()) + " at " +
                                spoken_time(at.minute_of_day));
    }
    robot().say("You have " + std::to_string(all.size()) + (all.size() == 1 ? " reminder: " : " reminders: ") +
                join_and(texts) + (all.size() > 5 ? ", and more." : "."));
  }

  struct Entry {
    int minute_of_day;
    std::string text;
  };

  // The reminders that fire on local `day`: one-off ones on that day, and recurring ones
  // whose rule includes the day (from their next occurrence on).
  void agenda(date::local_days day) {
    const std::vector<Entry> entries = entries_on(day);
    const std::string when = spoken_day(day, today());
    if (entries.empty()) {
      robot().say("You have nothing on your schedule " + when + ".");
      return;
    }
    std::vector<std::string> texts;
    for (const Entry& e : entries) texts.push_back(e.text);
    robot().say(capital(when) + ": " + join_and(texts) + ".");
  }

  // "next week", "this weekend": each day that has something, in order.
  void agenda_range(date::local_days first, int days) {
    std::vector<std::string> parts;
    for (int i = 0; i < days; ++i) {
      const date::local_days day = first + date::days(i);
      const std::vector<Entry> entries = entries_on(day);
      if (entries.empty()) continue;
      std::vector<std::string> texts;
      for (const Entry& e : entries) texts.push_back(e.text);
      parts.push_back(capital(spoken_day(day, today())) + ": " + join_and(texts) + ".");
    }
    if (parts.empty()) {
      auto bare = [this](date::local_days d) {  // "Monday, 7 December", not "on Monday, ..."
        std::string t = spoken_day(d, today());
        return t.rfind("on ", 0) == 0 ? t.substr(3) : t;
      };
      robot().say("You have nothing on your schedule from " + bare(first) + " to " +
                  bare(first + date::days(days - 1)) + ".");
      return;
    }
    std::string text;
    for (const std::string& p : parts) text += (text.empty() ? "" : " ") + p;
    robot().say(text);
  }

  std::vector<Entry> entries_on(date::local_days day) {
    const json all = robot().schedule_list(0, std::numeric_limits<std::int64_t>::max());
    std::vector<Entry> entries;
    for (const json& r : all) {
      const LocalTime next = parse_local(r.at("at").get<std::string>());
      if (next.day > day) continue;
      const json recurrence = r.value("recurrence", json::object());
      const std::string kind = recurrence.value("kind", "once");
      const std::string title = second_person(r.value("title", ""));
      const std::vector<std::string> days = weekdays_of(recurrence);
      const bool day_listed = days.empty() || std::find(days.begin(), days.end(),
                                                         kWeekdayNames[monday_based(day)]) != days.end();
      if (kind == "once") {
        if (next.day == day) entries.push_back({next.minute_of_day, title + " at " + spoken_time(next.minute_of_day)});
      } else if (kind == "daily" || (kind == "weekdays" && monday_based(day) < 5) ||
                 (kind == "weekly" && day_listed)) {
        entries.push_back({next.minute_of_day, title + " at " + spoken_time(next.minute_of_day)});
      } else if (kind == "interval" && day_listed) {
        entries.push_back({next.day == day ? next.minute_of_day : 0,
                           title + " " + spoken_recurrence(recurrence, next.minute_of_day)});
      }
    }
    std::stable_sort(entries.begin(), entries.end(),
                     [](const Entry& a, const Entry& b) { return a.minute_of_day < b.minute_of_day; });
    return entries;
  }

  // The words of `task` a title must contain ("my pills" -> "pill"), without the words that
  // say nothing about which ("the", "reminder", "appointment", ...: `generic`).
  static std::vector<std::string> wanted_words(const std::string& task,
                                               std::initializer_list<const char*> generic) {
    std::vector<std::string> wanted;
    for (std::string w : words_of(lower(task))) {
      w = without_possessive(w);
      auto says_nothing = [&](const std::string& word) {
        // "with", "about", "for": "my appointment with the dentist" is the dentist's.
        return word == "the" || word == "my" || word == "a" || word == "an" || word == "to" ||
               word == "with" || word == "about" || word == "for" ||
               std::any_of(generic.begin(), generic.end(),
                           [&](const char* g) { return word == g; });
      };
      if (says_nothing(w)) continue;
      if (w.size() > 3 && w.back() == 's') w.pop_back();  // "pills" finds "pill" and back
      if (says_nothing(w)) continue;                      // "reminders"
      if (w == "alarm") w = "wake";  // an alarm is stored as kAlarmTitle, "time to wake up"
      wanted.push_back(w);
    }
    return wanted;
  }

  // The reminders whose title holds every wanted word, soonest first; every reminder but
  // the timers when nothing is wanted and `all_when_empty`.
  std::vector<json> matching(const std::vector<std::string>& wanted, bool all_when_empty) {
    std::vector<json> hits;
    for (const json& r : robot().schedule_list(0, std::numeric_limits<std::int64_t>::max())) {
      const std::string title = lower(r.value("title", ""));
      if (wanted.empty() ? all_when_empty && title != kTimerTitle : has_all(title, wanted)) {
        hits.push_back(r);
      }
    }
    return hits;
  }

  // Whether `title` holds every wanted word. People name the same pills many ways ("my
  // tablets", "my medicine"), so a word for medicine finds a title with any of them.
  static bool has_all(const std::string& title, const std::vector<std::string>& wanted) {
    static constexpr const char* kMedicine[] = {"pill", "tablet", "medicine", "medication",
                                                "med", "capsule", "drug", "dose"};
    auto is_medicine = [](std::string w) {
      if (w.size() > 3 && w.back() == 's') w.pop_back();
      return std::any_of(std::begin(kMedicine), std::end(kMedicine),
                         [&](const char* m) { return w == m; });
    };
    const std::vector<std::string> title_words = words_in(title);
    const bool about_medicine = std::any_of(title_words.begin(), title_words.end(), is_medicine);
    return std::all_of(wanted.begin(), wanted.end(), [&](const std::string& w) {
      return is_medicine(w) ? about_medicine : title.find(w) != std::string::npos;
    });
  }

  // "when is my dentist appointment" -> the soonest that matches; "my next appointment" ->
  // the soonest of all. `how_long` ("how long until my appointment") says first how long
  // it is from now.
  void when_is(const std::string& task, bool how_long = false) {
    const std::vector<std::string> wanted =
        wanted_words(task, {"next", "appointment", "appointments", "reminder", "event", "thing",
                            "on", "calendar", "schedule", "of", "in", "have", "need", "got"});
    const std::vector<json> hits = matching(wanted, true);
    if (hits.empty()) {
      robot().say(wanted.empty()
                      ? "You have nothing on your schedule."
                      : "I don't see " + yours(task) + " on your schedule.");
      return;
    }
    const std::string title = capital(second_person(hits[0].value("title", "")));
    if (!how_long) return robot().say(title + ": " + spoken_when(hits[0]) + ".");
    const std::int64_t next = hits[0].value("next_fire_utc_ms", std::int64_t{0});
    robot().say(title + ": " + time_until(next, parse_local(hits[0].at("at").get<std::string>())) +
                ", " + spoken_when(hits[0]) + ".");
  }

  // "in 25 minutes", "in 2 hours and 10 minutes", "in about 5 hours" (also tomorrow's),
  // "in 3 days" (by the calendar: Thursday is in 3 days on a Monday evening too), "in about
  // 3 weeks".
  std::string time_until(std::int64_t utc_ms, const LocalTime& at) {
    const std::int64_t minutes = std::max<std::int64_t>(0, (utc_ms - robot().now_ms()) / 60000);
    const auto days = (at.day - today()).count();
    auto count = [](std::int64_t n, const char* unit) {
      return std::to_string(n) + " " + unit + (n == 1 ? "" : "s");
    };
    if (minutes < 1) return "in less than a minute";
    if (minutes < 60) return "in " + count(minutes, "minute");
    if (days <= 1 && minutes < 3 * 60) {
      const std::int64_t m = minutes % 60;
      return "in " + count(minutes / 60, "hour") + (m ? " and " + count(m, "minute") : "");
    }
    if (days <= 1) return "in about " + count((minutes + 30) / 60, "hour");  // 26 h: no "1 day"
    if (days < 14) return "in " + count(days, "day");
    return "in about " + count((days + 3) / 7, "week");
  }

  // Added at the new time before the old one is removed: if the host fails in between, the
  // appointment is there twice, never lost.
  void move(const marvin::Request& request) {
    const std::string task = request.slots.at("task").get<std::string>();
    const json& when = request.slots.at("when");
    const std::vector<std::string> wanted =
        wanted_words(task, {"appointment", "reminder", "event", "it", "that", "time", "date"});
    const std::vector<json> hits = matching(wanted, true);
    if (hits.empty()) {
      robot().say(wanted.empty() ? "You have nothing on your schedule to move."
                                 : "I don't see " + yours(task) + " on your schedule.");
      return;
    }
    const json& old = hits.front();  // the soonest
    const LocalTime was = parse_local(old.at("at").get<std::string>());
    LocalTime to = parse_local(when.at("at").get<std::string>());
    const bool time_given = when.value("time_given", true);
    const bool day_given = when.value("day_given", true);
    const json recurrence = old.value("recurrence", json::object());
    const bool once = recurrence.value("kind", "once") == "once";
    if (!once && (day_given || !time_given)) {
      robot().say("That reminder repeats " + spoken_recurrence(recurrence, was.minute_of_day) +
                  ". I can only move it to another time of day, for example \"move it to 10 "
                  "AM\".");
      return;
    }
    if (once && !time_given) to.minute_of_day = was.minute_of_day;  // "to Thursday": same time
    if (once && !day_given) to.day = was.day;  // "to 3 pm": on its own day, not the next 3 PM
    json moved = {{"title", old.value("title", "")}, {"at", local_text(to)}};
    if (old.contains("time_zone")) moved["time_zone"] = old["time_zone"];
    if (!once) moved["recurrence"] = recurrence;
    const json created = robot().schedule_add(moved);
    robot().schedule_remove(old.at("id").get<std::int64_t>());
    robot().say("OK, I moved it. " + capital(second_person(old.value("title", ""))) + ": " +
                spoken_when(created) + ".");
  }

  // The inverse of parse_local: "YYYY-MM-DDTHH:MM".
  static std::string local_text(const LocalTime& t) {
    return date::format("%FT%R", t.day + std::chrono::minutes{t.minute_of_day});
  }

  void cancel(const std::string& task) {
    // "all my", "all of them", "every": every reminder, after a question.
    const std::vector<std::string> wanted =
        wanted_words(task, {"reminder", "all", "every", "of", "them", "appointment", "event",
                            "anymore", "any", "more"});
    const std::vector<std::string> said = words_of(lower(task));
    const bool all = std::find(said.begin(), said.end(), "all") != said.end() ||
                     std::find(said.begin(), said.end(), "every") != said.end();
    const std::vector<json> hits = matching(wanted, all);
    const bool everything = all && wanted.empty();
    if (everything && hits.empty()) {
      robot().say("You have no reminders to cancel.");
      return;
    }
    // Several, by "all": asked without reading them out (one is cancelled as any one is).
    if (everything && hits.size() > 1) {
      const std::string answer = lower(robot().ask("You have " + std::to_string(hits.size()) +
                                                   " reminders. Should I cancel all of them?"));
      if (!said_yes(answer)) {
        robot().say("OK, I kept them.");
        return;
      }
      for (const json& r : hits) robot().schedule_remove(r.at("id").get<std::int64_t>());
      robot().say("OK, I cancelled all " + std::to_string(hits.size()) + " reminders.");
      return;
    }
    if (hits.empty() && is_alarm(task)) {
      // "Stop the alarm" right after it rang: it rang once and is over.
      const std::optional<json> fired = last_fired();
      robot().say(fired && fired->value("title", "") == kAlarmTitle ? "OK, the alarm is off."
                                                                    : "You have no alarm set.");
      return;
    }
    if (hits.empty()) {
      robot().say("I couldn't find a reminder about " + second_person(task) + ".");
      return;
    }
    if (hits.size() > 1) {
      std::vector<std::string> titles;
      for (const json& r : hits) {
        const LocalTime at = parse_local(r.at("at").get<std::string>());
        titles.push_back(second_person(r.value("title", "")) + " at " + spoken_time(at.minute_of_day));
      }
      const std::string answer = lower(robot().ask(
          "I found " + std::to_string(hits.size()) + " reminders: " + join_and(titles) +
          ". Should I cancel all of them?"));
      if (!said_yes(answer)) {
        robot().say("OK, I kept them.");
        return;
      }
    }
    for (const json& r : hits) robot().schedule_remove(r.at("id").get<std::int64_t>());
    robot().say(hits.size() == 1 && hits[0].value("title", "") == kAlarmTitle
                    ? std::string("OK, I cancelled the alarm.")
                : hits.size() == 1
                    ? "OK, I cancelled " + cancelled(hits[0].value("title", "")) + "."
                    : "OK, I cancelled all " + std::to_string(hits.size()) + " reminders.");
  }

  // The zone a reminder's times are spoken in: its own, else the owner's.
  const date::time_zone* zone_of(const json& reminder) {
    const std::string name = reminder.value("time_zone", "");
    return date::locate_zone(name.empty() ? robot().time_zone() : name);
  }

  // The reminder announced last, unless it was cancelled since.
  std::optional<json> last_fired() {
    std::optional<json> fired = robot().schedule_last_fired();
    if (fired && fired->value("state", "active") == "cancelled") return std::nullopt;
    return fired;
  }

  void snooze(const marvin::Request& request) {
    std::int64_t seconds = 10 * 60;
    if (auto it = request.slots.find("duration"); it != request.slots.end() && it->is_number_integer())
      seconds = it->get<std::int64_t>();
    if (seconds <= 0) {
      robot().say("Sorry, I can only snooze a reminder for some time from now.");
      return;
    }
    const std::optional<json> fired = last_fired();
    if (!fired && request.slots.contains("duration")) {
      // "Remind me in an hour" with nothing announced: a new reminder, an hour from now
      // (not "snooze it for ten minutes", "remind me again in five minutes").
      const std::vector<std::string> said = words_of(lower(request.utterance));
      const auto has = [&](const char* w) {
        return std::find(said.begin(), said.end(), w) != said.end();
      };
      if (has("remind") && !has("again")) return remind_in(request, seconds);
    }
    if (!fired) {
      robot().say("There is no reminder to snooze.");
      return;
    }
    const std::int64_t until = robot().now_ms() + seconds * 1000;
    // Returns once the new time is durably stored; only then do we say OK.
    robot().schedule_snooze(fired->at("id").get<std::int64_t>(), until);
    const auto local = zone_of(*fired)->to_local(
        date::sys_time<std::chrono::milliseconds>{std::chrono::milliseconds{until}});
    const auto day = date::floor<date::days>(local);
    const int minute = static_cast<int>(
        std::chrono::duration_cast<std::chrono::minutes>(local - day).count());
    std::string when = "at " + spoken_time(minute);
    if (day != date::floor<date::days>(zone_of(*fired)->to_local(
                   date::sys_time<std::chrono::milliseconds>{std::chrono::milliseconds{robot().now_ms()}})))
      when = spoken_day(day, today()) + " " + when;
    robot().say("OK, I'll remind you again " + when + ".");
  }

  void remind_in(const marvin::Request& request, std::int64_t seconds) {
    marvin::Request reminder = request;
    reminder.slots = json::object();
    reminder.slots["when"] = {{"at", local_minute(robot().now_ms() + seconds * 1000)},
                              {"time_zone", robot().time_zone()}};
    remind(reminder);
  }

  // Unix ms -> the owner's local "YYYY-MM-DDTHH:MM", to the minute.
  std::string local_minute(std::int64_t unix_ms) {
    const auto t = date::sys_time<std::chrono::milliseconds>{std::chrono::milliseconds{unix_ms}};
    return date::format("%Y-%m-%dT%H:%M", date::locate_zone(robot().time_zone())
                                              ->to_local(date::floor<std::chrono::minutes>(t)));
  }

  void done(const std::string& utterance) {
    std::optional<json> fired = last_fired();
    // "I took my pills" with no reminder announced (Marvin was off, or the pills came
    // first): the soonest medicine reminder, so that the log knows.
    if (!fired && has_all(lower(utterance), {"pill"})) {
      const std::vector<json> medicine = matching({"pill"}, false);
      if (!medicine.empty()) fired = medicine.front();
    }
    if (!fired) {
      robot().say("There is no reminder to mark as done.");
      return;
    }
    const std::string title = fired->value("title", "");
    // A one-off reminder is already retired (state "done") by the scheduler once it has
    // fired, so "I took them" right after it is the normal case. It is acknowledged all
    // the same, so that every "I took them" is in the owner's event log, where "did I take
    // my pills?" and the carer's page find it. Returns once the change is durably stored;
    // only then do we say so.
    robot().schedule_done(fired->at("id").get<std::int64_t>());
    robot().say("Well done, I've marked '" + title + "' as done.");
  }

  // "did I take my pills?", "have I done my exercises today?", "did I forget my tablets?":
  // the reminders marked done today (the "reminder_done" events the store writes for
  // schedule_done), by the words of the task; without one, when the next reminder is.
  void was_done(const marvin::Request& request) {
    const std::string task = request.slots.value("task", "");
    std::vector<std::string> wanted = wanted_words(
        task, {"them", "it", "that", "today", "yet", "already", "this", "morning", "evening",
               "tonight", "reminder", "your"});
    // "have I watered the plants" finds "water the plants".
    for (std::string& w : wanted) {
      if (w.size() > 5 && w.compare(w.size() - 2, 2, "ed") == 0) w.resize(w.size() - 2);
    }
    const std::vector<std::string> said = words_in(request.utterance);
    const bool forgot = std::any_of(said.begin(), said.end(), [](const std::string& w) {
      return w == "forget" || w == "forgot" || w == "forgotten";
    });
    const date::time_zone* zone = date::locate_zone(robot().time_zone());
    const auto midnight = zone->to_sys(today(), date::choose::earliest);
    const std::int64_t since =
        std::chrono::duration_cast<std::chrono::milliseconds>(midnight.time_since_epoch()).count();
    std::string title;
    std::vector<std::string> times;  // oldest first
    for (const json& e : robot().events_list("reminder_done", since)) {  // newest first
      const std::string message = e.value("message", "");
      const std::size_t open = message.find('\''), close = message.rfind('\'');
      if (open == std::string::npos || close <= open) continue;
      const std::string done_title = message.substr(open + 1, close - open - 1);
      if (!has_all(lower(done_title), wanted)) continue;
      if (title.empty()) title = done_title;
      if (done_title != title) continue;  // the latest one's, said once
      const auto local = zone->to_local(date::sys_time<std::chrono::milliseconds>{
          std::chrono::milliseconds{e.value("time_unix_ms", std::int64_t{0})}});
      const auto minutes = std::chrono::duration_cast<std::chrono::minutes>(
          local - date::floor<date::days>(local));
      times.insert(times.begin(), "at " + spoken_time(static_cast<int>(minutes.count())));
    }
    if (!times.empty()) {
      robot().say(std::string(forgot ? "No, you" : "Yes, you") + " marked '" + title +
                  "' as done today " + join_and(times) + ".");
      return;
    }
    const std::string not_told = wanted.empty()
                                     ? "You haven't marked anything as done today."
                                     : "You haven't told me today that you did.";
    const std::vector<json> coming = matching(wanted, false);
    if (wanted.empty() || coming.empty()) {
      robot().say(not_told + " When a reminder has been done, tell me \"done\", and I'll keep "
                             "track.");
      return;
    }
    const LocalTime at = parse_local(coming[0].at("at").get<std::string>());
    robot().say(not_told + " Your next reminder to " + second_person(coming[0].value("title", "")) +
                " is " + spoken_day(at.day, today()) + " at " + spoken_time(at.minute_of_day) +
                ".");
  }

  void add_contact(const marvin::Request& request) {
    // "save Tom's number as ...": the name is Tom.
    std::string name = without_possessive(request.slots.at("name").get<std::string>());
    // "add a contact Mary Jones 555 1234" has no word between the two slots, and the name
    // took only "mary": the words before the first digit are still the name's, less the
    // template's optional words ("with the number 12") that may land there too.
    const std::string slot = request.slots.at("number").get<std::string>();
    const auto digit = [](unsigned char c) { return std::isdigit(c) != 0; };
    std::string heard;
    bool in_number = std::none_of(slot.begin(), slot.end(), digit);  // "banana": said back
    for (const std::string& w : words_of(slot)) {
      in_number = in_number || w == "plus" || std::any_of(w.begin(), w.end(), digit);
      static const std::set<std::string> kBetween{"with", "the", "phone", "number", "is",
                                                  "and", "his", "her", "their"};
      const bool between = kBetween.count(lower(w)) != 0;
      if (in_number && !(heard.empty() && between)) {
        heard += (heard.empty() ? "" : " ") + w;
      } else if (!in_number && !between) {
        name += " " + w;
      }
    }
    name = capitalised(name);
    std::string number;
    int digits = 0;
    for (const std::string& w : words_of(lower(heard))) {
      if (w == "plus" && number.empty()) {
        number = "+";
        continue;
      }
      for (char c : w) {
        if (std::isdigit(static_cast<unsigned char>(c))) {
          number += c;
          ++digits;
        } else if (c == '+' && number.empty()) {
          number += c;
        }
      }
      number += ' ';  // keep the groups the user spoke
    }
    while (!number.empty() && number.back() == ' ') number.pop_back();
    if (digits < 3) {
      robot().say("Sorry, \"" + heard + "\" doesn't sound like a phone number. I didn't add " + name + ".");
      return;
    }
    robot().contacts_add({{"name", name}, {"phone_numbers", {number}}});
    robot().say("OK, I added " + name + " with the number " + spoken_number(number) + ".");
  }

  // "delete Peter from my contacts": asked first, as the number may be written nowhere else.
  void remove_contact(const std::string& said) {
    std::string name = without_possessive(said);
    static const std::set<std::string> kEveryone{"all",        "everyone",    "everybody",
                                                 "everything", "all of them", "every contact",
                                                 "them all"};
    if (kEveryone.count(lower(name)) != 0) {
      // The address book is what "call my daughter" and "call for help" rely on: emptied by
      // one misheard sentence, it could not be said back. One at a time, by name.
      robot().say("I remove contacts one at a time. Tell me the name of the one to remove.");
      return;
    }
    const json found = find_contacts(name);
    if (found.empty()) {
      robot().say("I don't have a contact called " + capitalised(name) + ".");
      return;
    }
    if (found.size() > 1) {
      std::vector<std::string> names;
      for (const json& c : found) names.push_back(c.value("name", ""));
      robot().say("You have " + std::to_string(found.size()) + " contacts called " +
                  capitalised(name) + ": " + join_and(names) +
                  ". Tell me the full name of the one to remove.");
      return;
    }
    const std::string full = found[0].value("name", "");
    if (!said_yes(robot().ask("Remove " + full + " from your contacts?"))) {
      robot().say("OK, I kept " + full + ".");
      return;
    }
    robot().contacts_remove(found[0].at("id").get<std::int64_t>());
    robot().say("OK, I removed " + full + " from your contacts.");
  }

  // The contacts a spoken name means. Speech has no apostrophe: "my doctors number" is my
  // doctor's, so a name ending in "s" that finds nobody is tried without it (and `name`
  // loses it too, to be said back).
  json find_contacts(std::string& name) {
    json found = robot().contacts_find(name);
    if (found.empty() && name.size() > 1 && name.back() == 's') {
      json without = robot().contacts_find(name.substr(0, name.size() - 1));
      if (!without.empty()) {
        name.pop_back();
        found = std::move(without);
      }
    }
    return found;
  }

  // "your daughter Anna Schmidt, Doctor Brown and Tom": the relation says who a name is,
  // unless the name says it already. At most ten are read out.
  void list_contacts() {
    const json all = robot().contacts_list();
    if (all.empty()) {
      robot().say("You have no contacts yet. To add one, say \"add a contact\".");
      return;
    }
    constexpr std::size_t kReadOut = 10;
    std::vector<std::string> names;
    for (const json& c : all) {
      if (names.size() == kReadOut) break;
      const std::string name = c.value("name", "");
      const std::string relation = c.value("relation", "");
      const bool said = relation.empty() || lower(name).find(lower(relation)) != std::string::npos;
      names.push_back(said ? name : "your " + relation + " " + name);
    }
    if (all.size() == 1) {
      robot().say("You have one contact: " + names[0] + ".");
    } else if (all.size() <= kReadOut) {
      robot().say("You have " + std::to_string(all.size()) + " contacts: " + join_and(names) + ".");
    } else {
      robot().say("You have " + std::to_string(all.size()) + " contacts. The first ten: " +
                  join_and(names) + ".");
    }
  }

  void contact_number(std::string name) {
    name = without_possessive(name);
    const json found = find_contacts(name);
    if (found.empty()) {
      robot().say("I don't have a contact called " + capitalised(name) + ".");
      return;
    }
    std::vector<std::string> parts;
    for (const json& c : found) {
      const std::string full = c.value("name", "");
      const json numbers = c.value("phone_numbers", json::array());
      if (numbers.empty() && !c.value("sip_uris", json::array()).empty()) {
        // An internet phone address only: no number to read out, but a call works.
        parts.push_back("I have no phone number for " + full + ", but I can call " + full +
                        ": say \"call " + full + "\"");
      } else if (numbers.empty()) {
        parts.push_back("I don't have a number for " + full);
      } else {
        parts.push_back(full + "'s number is " + spoken_number(numbers[0].get<std::string>()));
      }
    }
    robot().say(join_and(parts) + ".");
  }
};

}  // namespace

MARVIN_SKILL(ScheduleSkill, "schedule")
