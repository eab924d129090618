#include "interpret/eval_labels.h"

namespace marvin::interpret {

const std::vector<std::pair<std::string, std::string>>& default_eval_labels() {
  // The built-in skills and the example skills (skills-examples/).
  static const std::vector<std::pair<std::string, std::string>> kLabels{
      {"time/time", "time"},
      {"time/day", "date"},
      {"schedule/remind", "reminder_set"},
      {"schedule/snooze", "reminder_set"},
      {"schedule/list_reminders", "reminder_query"},
      {"schedule/agenda", "schedule_query"},
      {"schedule/agenda_today", "schedule_query"},
      {"schedule/when_is", "schedule_query"},
      {"schedule/add_event", "schedule_change"},
      {"schedule/have_event", "schedule_change"},
      {"schedule/cancel", "schedule_change"},
      {"schedule/move", "schedule_change"},
      {"schedule/set_timer", "timer"},
      {"schedule/timer_left", "timer"},
      {"schedule/cancel_timer", "timer"},
      {"hello/hello", "greeting"},
      {"hello/about", "about"},
      {"hello-lua/hello", "greeting"},
      {"hello-lua/about", "about"},
      {"medication/add", "reminder_set"},
      {"call/*", "call"},
      {"phone/unwell", "unwell"},  // no label of the set: never right, and acted on
      {"phone/lonely", "lonely"},
      {"phone/*", "call"},
      {"home/*", "smart_home"},  // skills-builtin/home: turn_on, turn_off, set_level, ...
  };
  return kLabels;
}

std::string default_eval_label(const std::string& skill, const std::string& intent) {
  const auto& labels = default_eval_labels();
  for (const std::string& key : {skill + "/" + intent, skill + "/*"}) {
    for (const auto& [row, label] : labels) {
      if (row == key) return label;
    }
  }
  return intent;
}

const char* builtin_eval_label(Builtin b) {
  switch (b) {
    case Builtin::kStop:
      return "cancel";
    case Builtin::kYes:
      return "yes";
    case Builtin::kNo:
      return "no";
    case Builtin::kRepeat:
      return "repeat";
    case Builtin::kNone:
      break;
  }
  return nullptr;
}

}  // namespace marvin::interpret
