// Template matching that forgives what people add and leave out, at a cost.
//
// The same compiled template program as matcher.h, run with more moves, each with a
// cost (lower is better; an exact parse costs 0):
//   extra word      an utterance word the template does not have (before, after or inside:
//                   "could you tell me the time please") .................. kExtraWord
//   missing word    a template word the utterance does not say ............ kMissingWord
//   swapped words   two adjacent template words in the other order ("what time it is")
//                   ......................................................... kSwap
//   missing slot    a slot the utterance does not fill (asked for later) ... kMissingSlot
//   stem / synonym  "reminders" for "reminder" (Snowball stem), "alarm" for "reminder" (a
//                   synonym the skill declares, or a built-in one) ....... kStem, kSynonym
// The best parse has the lowest cost, then the most literal words; nothing above kMaxCost is
// returned. Bounded by a step budget like the exact matcher, so it cannot stall the host.
#pragma once

#include <optional>
#include <span>
#include <string>
#include <unordered_map>
#include <vector>

#include "interpret/matcher.h"
#include "interpret/template.h"

namespace marvin::interpret {

struct TolerantCosts {
  static constexpr float kExtraWord = 1.0F;
  static constexpr float kMissingWord = 1.25F;
  static constexpr float kMissingSlot = 1.0F;
  static constexpr float kSwap = 0.5F;
  static constexpr float kStem = 0.25F;
  static constexpr float kSynonym = 0.5F;
  static constexpr float kMaxCost = 5.0F;
};

// An utterance prepared once for every template it is tried against.
struct TolerantInput {
  std::span<const std::string> words;
  std::span<const int> ids;                 // vocabulary ids (kUnknown if none)
  std::span<const std::string> stems;       // stem(words[i])
};

// For one intent: utterance word -> template word ids it may stand for.
using SynonymTable = std::unordered_map<std::string, std::vector<int>>;

struct TolerantMatch {
  float cost = 0;
  int literal_words = 0;
  std::vector<SlotCapture> slots;
};

// `word_stems[id]` is the stem of vocabulary word `id`.
std::optional<TolerantMatch> match_tolerant(const CompiledTemplate& compiled,
                                            const TolerantInput& input,
                                            const std::vector<std::string>& word_stems,
                                            const SynonymTable& synonyms,
                                            const SlotReader& reader);

}  // namespace marvin::interpret
