// Runs one compiled template against one normalised utterance.
//
// Backtracking over the template program: every way the whole utterance can be consumed is
// explored (bounded by a step budget, so a pathological template cannot stall the host), and
// the best parse is kept: most literal words, then fewest words given to text slots, then the
// first found (alternatives in written order, optional parts taken before skipped, slots
// shortest first). Slot spans are checked by the caller's SlotReader.
#pragma once

#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "interpret/interpreter.h"
#include "interpret/template.h"

namespace marvin::interpret {

class SlotReader {
 public:
  virtual ~SlotReader() = default;
  // The value of slot `slot` if `words` (all of them) is one; nullopt otherwise.
  virtual std::optional<SlotValue> read(int slot, std::span<const std::string> words) const = 0;
  // True if the slot is free text (its words count against the match's rank).
  virtual bool is_text(int slot) const = 0;
  // The most words the slot can take.
  virtual std::size_t max_words(int slot) const = 0;
};

struct SlotCapture {
  int slot = -1;
  SlotValue value;
};

struct TemplateMatch {
  int literal_words = 0;
  int text_words = 0;
  std::vector<SlotCapture> slots;
};

// True if `a` ranks strictly above `b` (more literal words, then fewer text words).
bool ranks_above(const TemplateMatch& a, const TemplateMatch& b);

// `words` and `word_ids` are the same utterance (ids from the template's Vocabulary,
// Vocabulary::kUnknown for words no template uses).
std::optional<TemplateMatch> match_template(const CompiledTemplate& compiled,
                                            std::span<const std::string> words,
                                            std::span<const int> word_ids,
                                            const SlotReader& reader);

}  // namespace marvin::interpret
