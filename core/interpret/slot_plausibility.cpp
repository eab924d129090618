#include "interpret/slot_plausibility.h"

#include <algorithm>
#include <array>

#include "interpret/wordnet.h"

namespace marvin::interpret {
namespace {

constexpr std::array<std::string_view, 10> kEntitySlotNames{
    "what", "who", "name", "thing", "object", "item", "person", "device", "room", "place"};

constexpr std::array<std::string_view, 22> kFunctionWords{
    "the",  "a",    "an", "of",    "to",   "for",  "in", "on",   "at",   "and", "or",
    "with", "from", "by", "about", "into", "onto", "as", "than", "then", "but", "nor"};

// Leading words that only say which one ("the", "my", "some").
constexpr std::array<std::string_view, 19> kDeterminers{
    "the",  "a",    "an",    "my",    "your", "our", "his", "her",  "their", "its",
    "this", "that", "these", "those", "some", "any", "all", "both", "every"};

// Words that end the name of a thing and start what is said about it.
constexpr std::array<std::string_view, 28> kHeadEnds{
    "of",   "for",   "on",  "about", "in",    "to",   "with",  "from", "at",    "by",
    "that", "which", "who", "whom",  "whose", "when", "where", "if",   "while", "because",
    "and",  "or",    "is",  "are",   "was",   "were", "will",  "would"};

// Words that refer to a person or thing already known; the skill resolves them.
constexpr std::array<std::string_view, 16> kReferences{
    "it",     "them",    "him",       "her",      "everyone",   "everybody", "someone", "somebody",
    "anyone", "anybody", "something", "anything", "everything", "one",       "mine",    "yours"};

// Words that rank places in the world ("the nearest ...", "the best ...").
constexpr std::array<std::string_view, 14> kSuperlatives{
    "nearest", "closest", "best",    "cheapest", "worst",   "fastest", "quickest",
    "latest",  "newest",  "biggest", "largest",  "highest", "lowest",  "top"};

// A subject pronoun after the first word starts a clause: "the temperature it will be".
constexpr std::array<std::string_view, 8> kClauseStarts{"it",  "i",  "you",  "he",
                                                        "she", "we", "they", "there"};

// First words of a question or clause, never of a name: "where is {what}" tolerantly fits
// "where does cannabis come from" with "does cannabis", and "where have you been" with
// "have you been".
constexpr std::array<std::string_view, 21> kQuestionStarts{
    "do",   "does", "did", "why", "how", "whether", "can", "could", "should", "would", "shall",
    "must", "have", "has", "had", "is",  "are",     "was", "were",  "will",   "am"};

// Short names of household devices that WordNet files only under other senses ("ac":
// actinium, alternating current).
constexpr std::array<std::string_view, 6> kDeviceAbbreviations{"ac", "a/c", "hvac",
                                                               "tv", "pc",  "aircon"};

constexpr int kNounArtifact = 6;  // WordNet lexname noun.artifact

// WordNet lexnames of abstract nouns (see the header).
constexpr std::array<int, 13> kAbstract{4, 7, 9, 10, 11, 12, 16, 19, 22, 24, 25, 26, 28};

template <std::size_t N>
bool listed(const std::array<std::string_view, N>& table, std::string_view word) {
  return std::find(table.begin(), table.end(), word) != table.end();
}

}  // namespace

bool is_entity_slot(std::string_view slot_name) { return listed(kEntitySlotNames, slot_name); }

bool is_device_slot(std::string_view slot_name) { return slot_name == "device"; }

bool plausible_device(std::span<const std::string> words, const WordNet* wordnet) {
  if (wordnet == nullptr) return true;
  std::size_t begin = 0;
  while (begin + 1 < words.size() && listed(kDeterminers, words[begin])) ++begin;
  std::size_t end = begin;
  while (end < words.size() && !listed(kHeadEnds, words[end]) &&
         !(end > begin && listed(kClauseStarts, words[end]))) {
    ++end;
  }
  if (end == begin) return false;
  const std::string& head = words[end - 1];
  if (listed(kReferences, head)) return true;
  if (wordnet->noun_categories(head, 1).empty() && !wordnet->is_verb_adjective_or_adverb(head)) {
    return true;  // a name WordNet does not know
  }
  for (std::size_t i = begin; i < end; ++i) {
    if (listed(kDeviceAbbreviations, words[i])) return true;
    const std::vector<int> categories = wordnet->noun_categories(words[i], 4);
    if (std::find(categories.begin(), categories.end(), kNounArtifact) != categories.end()) {
      return true;
    }
  }
  return false;
}

bool only_function_words(std::span<const std::string> words) {
  return std::all_of(words.begin(), words.end(),
                     [](const std::string& w) { return listed(kFunctionWords, w); });
}

bool plausible_entity(std::span<const std::string> words, const WordNet* wordnet, bool strict) {
  if (words.empty() || only_function_words(words)) return false;
  if (listed(kQuestionStarts, words.front())) return false;
  std::size_t begin = 0;
  // "find her": the last word may be both a determiner and the reference.
  while (begin + 1 < words.size() && listed(kDeterminers, words[begin])) ++begin;
  std::size_t end = begin;
  while (end < words.size() && !listed(kHeadEnds, words[end]) &&
         !(end > begin && listed(kClauseStarts, words[end]))) {
    ++end;
  }
  if (end == begin) return false;
  // "the nearest gas station", "the best pizza place": a search of the world, not of a home.
  for (std::size_t i = begin; i < end; ++i) {
    if (listed(kSuperlatives, words[i])) return false;
  }
  const std::string& head = words[end - 1];
  if (listed(kReferences, head)) return true;
  if (listed(kFunctionWords, head) || listed(kDeterminers, head)) return false;
  if (wordnet == nullptr) return true;
  // A word WordNet knows only as a verb, adjective or adverb is none ("yet", "ridiculous").
  if (wordnet->noun_categories(head, 1).empty() && wordnet->is_verb_adjective_or_adverb(head)) {
    return false;
  }
  // One or two words with no article or possessive may be a name ("mark", "aunt felicity",
  // "grace"): WordNet files many first names under abstract nouns.
  if (!strict && begin == 0 && end == words.size() && words.size() <= 2) return true;
  auto concrete = [&](const std::string& word) {
    const std::vector<int> categories = wordnet->noun_categories(word, 3);
    return std::any_of(categories.begin(), categories.end(), [](int c) {
      return std::find(kAbstract.begin(), kAbstract.end(), c) == kAbstract.end();
    });
  };
  if (concrete(head)) return true;
  // "my glasses case": a thing WordNet knows before the head names what it is about.
  for (std::size_t i = begin; i + 1 < end; ++i) {
    if (concrete(words[i])) return true;
  }
  // A word WordNet does not know is a name ("bob"); one it knows only as a verb, adjective
  // or adverb is none ("yet").
  if (wordnet->noun_categories(head, 1).empty()) return !wordnet->is_verb_adjective_or_adverb(head);
  return false;
}

}  // namespace marvin::interpret
