#include "interpret/voice_change.h"

#include <algorithm>
#include <initializer_list>
#include <string>
#include <vector>

#include "interpret/normalizer.h"
#include "interpret/phrasing.h"

namespace marvin::interpret {
namespace {

bool in(const std::string& word, std::initializer_list<std::string_view> words) {
  return std::find(words.begin(), words.end(), word) != words.end();
}

// The direction a word names on its own ("slower", "louder"), or nullopt.
std::optional<VoiceChange> direction_of(const std::string& w) {
  if (in(w, {"slower", "slowly"})) return VoiceChange::kSlower;
  if (in(w, {"faster", "quicker", "quickly"})) return VoiceChange::kFaster;
  if (in(w, {"louder", "loudly"})) return VoiceChange::kLouder;
  if (in(w, {"quieter", "quietly", "softer", "softly"})) return VoiceChange::kQuieter;
  return std::nullopt;
}

// After "too": what is wrong now, so the change is the opposite ("too fast" -> slower).
std::optional<VoiceChange> opposite_of(const std::string& w) {
  if (in(w, {"fast", "quick", "quickly"})) return VoiceChange::kSlower;
  if (in(w, {"slow", "slowly"})) return VoiceChange::kFaster;
  if (in(w, {"loud", "loudly"})) return VoiceChange::kQuieter;
  if (in(w, {"quiet", "quietly", "soft", "softly", "low"})) return VoiceChange::kLouder;
  return std::nullopt;
}

// Words that may surround the direction in a request about the voice.
bool filler(const std::string& w) {
  return in(w, {"can",      "could",  "would",  "will",  "you",    "please", "a",        "bit",
                "little",   "lot",    "much",   "more",  "try",    "to",     "be",       "and",
                "marvin",   "hey",    "ok",     "just",  "now",    "speak",  "talk",     "say",
                "it",       "that",   "again",  "your",  "voice",  "i",      "need",     "want",
                "like",     "if",     "is",     "are",   "am",     "so",     "not",      "slightly",
                "thanks",   "thank",  "sorry",  "maybe", "for",    "me",     "talking",  "speaking"});
}

bool about_voice(const std::vector<std::string>& w) {
  return std::any_of(w.begin(), w.end(), [](const std::string& x) {
    return in(x, {"speak", "talk", "talking", "speaking", "voice", "say", "you"});
  });
}

}  // namespace

std::optional<VoiceChange> voice_change(std::string_view utterance) {
  const std::vector<std::string> w = strip_politeness(normalize(utterance));
  if (w.empty() || w.size() > 10) return std::nullopt;
  // "I can't hear you", "I can hardly hear you".
  for (std::size_t i = 0; i + 1 < w.size(); ++i) {
    if (w[i] == "hear" && w[i + 1] == "you" && i >= 1 &&
        (w[i - 1] == "hardly" || w[i - 1] == "cannot" ||
         (w[i - 1] == "not" && i >= 2 && w[i - 2] == "can"))) {
      return VoiceChange::kLouder;
    }
  }
  // "you're talking too fast", "your voice is too loud", "not so fast" (spoken to Marvin).
  for (std::size_t i = 0; i + 1 < w.size(); ++i) {
    const bool not_so = w[i] == "so" && i >= 1 && w[i - 1] == "not";
    if ((w[i] == "too" && about_voice(w)) || (not_so && (w.size() == 3 || about_voice(w)))) {
      if (auto change = opposite_of(w[i + 1]); change && i + 2 == w.size()) return change;
    }
  }
  // "speak slower", "louder please", "could you speak up a little", "talk more slowly".
  std::optional<VoiceChange> found;
  for (std::size_t i = 0; i < w.size(); ++i) {
    std::optional<VoiceChange> here = direction_of(w[i]);
    if (!here && w[i] == "up" && i >= 1 && in(w[i - 1], {"speak", "talk"})) here = VoiceChange::kLouder;
    if (here) {
      if (found && *found != *here) return std::nullopt;  // "louder and slower": one at a time
      found = here;
    } else if (!filler(w[i])) {
      return std::nullopt;  // "turn the radio louder", "walk slower"
    }
  }
  // A bare "slower" is about the voice; so is anything with "speak"/"talk"/"voice".
  if (found && (w.size() <= 2 || about_voice(w))) return found;
  return std::nullopt;
}

}  // namespace marvin::interpret
