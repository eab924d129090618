// The interpreter's registered intents in compiled form (shared by matching and the
// conflict check).
#pragma once

#include <string>
#include <vector>

#include "interpret/interpreter.h"
#include "interpret/slot_parsers.h"
#include "interpret/template.h"

namespace marvin::interpret {

struct CompiledIntent {
  IntentSpec spec;
  std::vector<PreparedSlot> slots;            // same order as spec.slots
  std::vector<CompiledTemplate> templates;    // same order as spec.templates
};

// Sentences claimed by intents of two different skills, one description per pair of
// intents (see Interpreter::conflicts()).
std::vector<std::string> find_conflicts(const std::vector<CompiledIntent>& intents,
                                        const Vocabulary& vocabulary);

}  // namespace marvin::interpret
