// The labels `marvin nlu eval` scores with (core/app/cli_nlu.cpp) and the tests that check the
// same rates: the shared development set's names for the intents of Marvin's skills, and for
// the dialogue words. A request is right when the intent chosen carries the line's label.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "interpret/interpreter.h"

namespace marvin::interpret {

// skill/intent -> label, in order; a "skill/*" row labels every intent of that skill.
const std::vector<std::pair<std::string, std::string>>& default_eval_labels();

// The label of `intent` of `skill` by default_eval_labels(): its own row, else its skill's
// "*" row, else the intent's own name.
std::string default_eval_label(const std::string& skill, const std::string& intent);

// "cancel" (stop), "yes", "no", "repeat"; nullptr for Builtin::kNone.
const char* builtin_eval_label(Builtin b);

}  // namespace marvin::interpret
