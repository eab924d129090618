#include "interpret/builtins.h"

#include <algorithm>
#include <array>
#include <string>
#include <utility>
#include <vector>

#include "interpret/normalizer.h"
#include "interpret/phrasing.h"

namespace marvin::interpret {
namespace {

struct Phrase {
  std::string_view text;
  Builtin meaning;
};

// Normalised forms ("one" would be "1"; none of these contain number words).
constexpr std::array kPhrases{
    Phrase{"stop", Builtin::kStop},
    Phrase{"cancel", Builtin::kStop},
    Phrase{"never mind", Builtin::kStop},
    Phrase{"nevermind", Builtin::kStop},
    Phrase{"stop it", Builtin::kStop},
    Phrase{"stop that", Builtin::kStop},
    Phrase{"cancel that", Builtin::kStop},
    Phrase{"cancel it", Builtin::kStop},
    Phrase{"abort", Builtin::kStop},
    Phrase{"halt", Builtin::kStop},
    Phrase{"quiet", Builtin::kStop},
    Phrase{"be quiet", Builtin::kStop},
    Phrase{"shut up", Builtin::kStop},
    Phrase{"enough", Builtin::kStop},
    Phrase{"that's enough", Builtin::kStop},
    Phrase{"forget it", Builtin::kStop},
    Phrase{"stop stop", Builtin::kStop},
    // The robot on the move: said to make it stand where it is.
    Phrase{"stand still", Builtin::kStop},
    Phrase{"stay still", Builtin::kStop},
    Phrase{"stay there", Builtin::kStop},
    Phrase{"stay where you are", Builtin::kStop},
    Phrase{"freeze", Builtin::kStop},
    Phrase{"yes", Builtin::kYes},
    Phrase{"yeah", Builtin::kYes},
    Phrase{"yep", Builtin::kYes},
    Phrase{"yup", Builtin::kYes},
    Phrase{"sure", Builtin::kYes},
    Phrase{"ok", Builtin::kYes},
    Phrase{"okay", Builtin::kYes},
    Phrase{"of course", Builtin::kYes},
    Phrase{"yes please", Builtin::kYes},
    Phrase{"correct", Builtin::kYes},
    Phrase{"right", Builtin::kYes},
    Phrase{"do it", Builtin::kYes},
    Phrase{"go ahead", Builtin::kYes},
    Phrase{"absolutely", Builtin::kYes},
    Phrase{"affirmative", Builtin::kYes},
    Phrase{"that's right", Builtin::kYes},
    Phrase{"please do", Builtin::kYes},
    Phrase{"yes do it", Builtin::kYes},
    Phrase{"no", Builtin::kNo},
    Phrase{"nope", Builtin::kNo},
    Phrase{"nah", Builtin::kNo},
    Phrase{"no thanks", Builtin::kNo},
    Phrase{"no thank you", Builtin::kNo},
    Phrase{"don't", Builtin::kNo},
    Phrase{"do not", Builtin::kNo},
    Phrase{"negative", Builtin::kNo},
    Phrase{"not now", Builtin::kNo},
    Phrase{"no don't", Builtin::kNo},
    Phrase{"repeat", Builtin::kRepeat},
    Phrase{"repeat that", Builtin::kRepeat},
    Phrase{"say that again", Builtin::kRepeat},
    Phrase{"say it again", Builtin::kRepeat},
    Phrase{"again", Builtin::kRepeat},
    Phrase{"pardon", Builtin::kRepeat},
    Phrase{"what did you say", Builtin::kRepeat},
    Phrase{"come again", Builtin::kRepeat},
    Phrase{"sorry what", Builtin::kRepeat},
    Phrase{"repeat please", Builtin::kRepeat},
    Phrase{"i do not think so", Builtin::kNo},
    Phrase{"not really", Builtin::kNo},
    Phrase{"certainly not", Builtin::kNo},
    Phrase{"of course not", Builtin::kNo},
    Phrase{"absolutely not", Builtin::kNo},
    Phrase{"that is wrong", Builtin::kNo},
    Phrase{"that is not right", Builtin::kNo},
    Phrase{"that is not correct", Builtin::kNo},
    Phrase{"that is false", Builtin::kNo},
    Phrase{"i disagree", Builtin::kNo},
    Phrase{"that is correct", Builtin::kYes},
    Phrase{"that is true", Builtin::kYes},
    Phrase{"i agree", Builtin::kYes},
    Phrase{"sounds good", Builtin::kYes},
    Phrase{"you are right", Builtin::kYes},
    Phrase{"i think so", Builtin::kYes},
    Phrase{"what was that", Builtin::kRepeat},
    Phrase{"what did you just say", Builtin::kRepeat},
    Phrase{"i did not hear you", Builtin::kRepeat},
    Phrase{"once more", Builtin::kRepeat},
    // Said in passing rather than as one word (written for Marvin, not from any test set).
    Phrase{"scratch that", Builtin::kStop},
    Phrase{"forget about it", Builtin::kStop},
    Phrase{"drop it", Builtin::kStop},
    Phrase{"leave it", Builtin::kStop},
    Phrase{"do not bother", Builtin::kStop},
    Phrase{"i changed my mind", Builtin::kStop},
    Phrase{"i have changed my mind", Builtin::kStop},
    Phrase{"call it off", Builtin::kStop},
    Phrase{"skip it", Builtin::kStop},
    Phrase{"that will be all", Builtin::kStop},
    Phrase{"sure thing", Builtin::kYes},
    Phrase{"go for it", Builtin::kYes},
    Phrase{"that works", Builtin::kYes},
    Phrase{"works for me", Builtin::kYes},
    Phrase{"alright", Builtin::kYes},
    Phrase{"all right", Builtin::kYes},
    Phrase{"by all means", Builtin::kYes},
    Phrase{"you got it", Builtin::kYes},
    Phrase{"uh huh", Builtin::kYes},
    Phrase{"i do", Builtin::kYes},
    Phrase{"yes i do", Builtin::kYes},
    Phrase{"that is it", Builtin::kYes},
    Phrase{"that is what i meant", Builtin::kYes},
    Phrase{"that is what i said", Builtin::kYes},
    Phrase{"what", Builtin::kRepeat},
    Phrase{"huh", Builtin::kRepeat},
    Phrase{"silence", Builtin::kStop},
    Phrase{"hush", Builtin::kStop},
    Phrase{"not at all", Builtin::kNo},
    Phrase{"no way", Builtin::kNo},
    Phrase{"not quite", Builtin::kNo},
    Phrase{"i do not", Builtin::kNo},
    Phrase{"that is not it", Builtin::kNo},
    Phrase{"that is not what i meant", Builtin::kNo},
    Phrase{"that is not what i said", Builtin::kNo},
    Phrase{"i do not want that", Builtin::kNo},
    Phrase{"definitely not", Builtin::kNo},
    Phrase{"please do not", Builtin::kNo},
    // Declining an offer in passing: "i'll pass" (normalised "i will pass"), "pass on that".
    // More after "pass" ("i will pass on that thanks") is read by by_head_word.
    Phrase{"pass", Builtin::kNo},
    Phrase{"i will pass", Builtin::kNo},
    Phrase{"i will give it a miss", Builtin::kNo},
    Phrase{"no need", Builtin::kNo},
    Phrase{"not necessary", Builtin::kNo},
};

bool in(std::string_view word, std::initializer_list<std::string_view> set) {
  for (std::string_view w : set) {
    if (w == word) return true;
  }
  return false;
}

// A head word and only harmless words after it: "cancel that now", "yes that is right",
// "no that is not correct". Content words ("cancel my dentist reminder") never qualify, so
// a request is never taken for a dialogue word.
Builtin by_head_word(std::vector<std::string> w) {
  // "never mind" is one word here, so that "never mind that" is not read as "never".
  for (std::size_t i = 0; i + 1 < w.size(); ++i) {
    if (w[i] == "never" && w[i + 1] == "mind") {
      w[i] = "nevermind";
      w.erase(w.begin() + static_cast<std::ptrdiff_t>(i) + 1);
    }
  }
  if (w.empty() || w.size() > 7) return Builtin::kNone;
  auto rest_in = [&](std::initializer_list<std::string_view> set) {
    for (std::size_t i = 1; i < w.size(); ++i) {
      if (!in(w[i], set)) return false;
    }
    return true;
  };
  const std::string& head = w[0];
  // "do not talk any more", "do not say anything else", "stop talking": be quiet.
  if (w.size() >= 3 && head == "do" && w[1] == "not" &&
      in(w[2], {"talk", "speak", "say", "continue", "go", "move"}) &&
      std::all_of(w.begin() + 3, w.end(), [](const std::string& x) {
        return in(x, {"any", "more", "anymore", "further", "now", "please", "to", "me", "anything",
                      "else", "on", "with", "it", "that", "again"});
      })) {
    return Builtin::kStop;
  }
  if (in(head, {"stop", "cancel", "abort", "halt", "quit", "terminate", "end", "scrap", "nevermind",
                "forget", "disregard", "ignore", "drop"}) &&
      rest_in({"it",       "that",  "this",    "now",         "everything", "all",
               "talking",  "right", "away",    "immediately", "the",        "current",
               "process",  "task",  "request", "action",      "operation",  "please",
               "off",      "stop",  "cancel",  "about",       "last",       "thing",
               "whatever", "what",  "you",     "are",         "doing",      "my",
               "command",  "then",  "there",   "nevermind",   "instead",    "moving",
               "walking",  "driving", "going", "looking",     "searching",  "here",
               "robot",    "marvin"})) {
    return Builtin::kStop;
  }
  if (in(head, {"yes",       "yeah",        "yep",        "yup",        "sure",      "correct",
                "right",     "affirmative", "absolutely", "definitely", "certainly", "indeed",
                "agreed",    "exactly",     "true",       "ok",         "okay",      "approved",
                "confirmed", "totally",     "alright",    "fine",       "precisely", "yea",
                "yah",       "ya",          "aye",        "perfect",    "great"}) &&
      rest_in({"that",       "is",         "it",      "right",     "correct",   "true",    "sure",
               "please",     "do",         "go",      "ahead",     "sounds",    "good",    "fine",
               "i",          "agree",      "thanks",  "thank",     "you",       "of",      "course",
               "definitely", "absolutely", "yes",     "yeah",      "thing",     "exactly", "so",
               "am",         "indeed",     "a",       "statement", "confirm",   "what",    "meant",
               "said",       "want",       "wanted",  "works",     "for",       "me",      "by",
               "all",        "means",      "perfect", "exactly",   "precisely", "alright", "ok",
               "okay",       "sir",        "let",     "us"})) {
    return Builtin::kYes;
  }
  if (in(head, {"no", "nope", "nah", "negative", "negatory", "never", "incorrect", "wrong", "false",
                "not"}) &&
      rest_in({"no",         "not",       "that",    "is",     "it",     "wrong",      "incorrect",
               "right",      "correct",   "thanks",  "thank",  "you",    "i",          "do",
               "think",      "so",        "way",     "false",  "meant",  "nope",       "certainly",
               "absolutely", "of",        "course",  "please", "really", "true",       "at",
               "all",        "happening", "invalid", "chance", "a",      "definitely", "nah",
               "what",       "said",      "want",    "wanted", "asked",  "for",        "quite",
               "sir",        "ever",      "exactly", "how",    "thats",  "sorry",      "don't",
               "dont"})) {
    return Builtin::kNo;
  }
  // "pass", "pass on that thanks": declining what was offered ("pass the salt" is a request).
  if (head == "pass" && rest_in({"on", "that", "it", "this", "thanks", "thank", "you", "for", "now",
                                 "time", "one"})) {
    return Builtin::kNo;
  }
  bool repeat = false;
  for (std::size_t i = 0; i < w.size(); ++i) {
    // "repeat that", "can you repeat the question", but not "repeat my shopping list".
    if ((w[i] == "repeat" || w[i] == "repeated") &&
        std::all_of(
            w.begin() + static_cast<std::ptrdiff_t>(i) + 1, w.end(), [](const std::string& x) {
              return in(x,
                        {"that",     "it",     "this",     "please", "again",  "yourself", "what",
                         "you",      "said",   "say",      "just",   "the",    "last",     "thing",
                         "question", "answer", "sentence", "1",      "more",   "time",     "once",
                         "me",       "one",    "for",      "now",    "slowly", "louder"});
            })) {
      repeat = true;
    }
    if (w[i] == "again" && i > 0 && in(w[i - 1], {"that", "it", "this", "say", "said"})) {
      repeat = true;
    }
    if (in(w[i], {"hear", "catch", "understand"}) && i >= 2 && w[i - 1] == "not" &&
        (w[i - 2] == "did" || w[i - 2] == "could")) {
      repeat = true;
    }
  }
  if (repeat && w.size() <= 10) return Builtin::kRepeat;
  return Builtin::kNone;
}

// Fillers and lead-ins before the dialogue word: "oh, never mind", "um no",
// "i want to cancel that", "you can stop now", "actually yes".
Builtin by_head_word_after_lead_in(const std::vector<std::string>& w) {
  std::size_t k = 0;
  while (k < w.size() && k < 4 &&
         in(w[k], {"oh", "um", "uh", "erm", "ah", "well", "hmm", "actually", "just", "so", "i",
                   "want", "would", "like", "to", "need", "let", "us", "you", "can", "could",
                   "please", "mean", "guess", "said", "hey",
                   // saying it again, louder: "i said no", "i repeat, stop", "i told you no"
                   "repeat", "told", "will",
                   // intensifiers: "hell no", "heck yes", "oh god no"
                   "hell", "heck", "god", "gosh",
                   // how people address an assistant that is not called by its name
                   "ai", "assistant", "robot", "computer", "bot"})) {
    ++k;
  }
  // "no, just cancel it", "no no stop": a no that leads into stopping is a stop (and only a
  // stop: "no yes" stays neither).
  std::size_t noes = k;
  while (noes < w.size() && noes < k + 2 && in(w[noes], {"no", "nope", "nah"})) ++noes;
  if (noes > k && noes < w.size()) {
    std::size_t after = noes;
    while (after < w.size() && in(w[after], {"just", "please", "actually", "oh", "um"})) ++after;
    if (after < w.size() &&
        by_head_word(std::vector<std::string>(w.begin() + static_cast<std::ptrdiff_t>(after),
                                              w.end())) == Builtin::kStop) {
      return Builtin::kStop;
    }
  }
  if (k == 0 || k == w.size()) return Builtin::kNone;
  return by_head_word(
      std::vector<std::string>(w.begin() + static_cast<std::ptrdiff_t>(k), w.end()));
}

// Edit distance at most one (a typo: "affirmitive", "corect").
bool one_edit_apart(std::string_view a, std::string_view b) {
  if (a.size() > b.size()) std::swap(a, b);
  if (b.size() - a.size() > 1) return false;
  std::size_t i = 0;
  while (i < a.size() && a[i] == b[i]) ++i;
  if (a.size() == b.size()) return a.substr(i + 1) == b.substr(i + 1);
  return a.substr(i) == b.substr(i + 1);
}

// +1 for a word that affirms, -1 for one that denies, 0 for neither. Long words also count
// with one typo.
int polarity_of(std::string_view word) {
  static constexpr auto kPositive = std::to_array<std::string_view>(
      {"yes", "true", "right", "correct", "accurate", "valid", "affirmative", "agree", "agreed",
       "accepted", "accept", "confirmed", "good", "sense"});
  static constexpr auto kNegative =
      std::to_array<std::string_view>({"no", "false", "wrong", "incorrect", "inaccurate", "invalid",
                                       "untrue", "disagree", "nope", "negative"});
  for (std::string_view w : kPositive) {
    if (word == w || (w.size() >= 7 && one_edit_apart(word, w))) return 1;
  }
  for (std::string_view w : kNegative) {
    if (word == w || (w.size() >= 7 && one_edit_apart(word, w))) return -1;
  }
  return 0;
}

// A short statement of agreement or denial in the person's own words: "the statement is
// true", "you are not wrong about that", "i would rather not", "invalid", "no good". Every
// word must be a polarity word, a negation or a harmless word (pronouns, "is", "statement",
// "i think", "i know"), so a request never qualifies; a negation flips the polarity word it
// precedes (within two words); all polarity words must then agree. A negation with no
// polarity word after a wish ("i would rather not", "i would prefer not") is a no.
Builtin by_polarity(const std::vector<std::string>& w) {
  if (w.empty() || w.size() > 9) return Builtin::kNone;
  // A question ("is that true", "are you good") asks, it does not answer.
  if (in(w[0], {"is", "are", "am", "was", "were", "do", "does", "did"})) return Builtin::kNone;
  static constexpr auto kHarmless = std::to_array<std::string_view>(
      {"i",       "you",        "it",      "this",      "that",      "is",     "are",    "was",
       "am",      "be",         "a",       "the",       "statement", "answer", "know",   "think",
       "telling", "tell",       "want",    "to",        "about",     "as",     "well",   "quite",
       "totally", "completely", "so",      "very",      "said",      "meant",  "makes",  "make",
       "would",   "rather",     "prefer",  "guess",     "sounds",    "seems",  "indeed", "really",
       "one",     "100",        "percent", "perfectly", "saying",    "say"});
  auto harmless = [&](const std::string& word) {
    return std::find(kHarmless.begin(), kHarmless.end(), word) != kHarmless.end();
  };
  int sign = 0;
  bool negated_wish = false;
  std::size_t negation_at = w.size();  // the last negation not yet used
  for (std::size_t i = 0; i < w.size(); ++i) {
    const std::string& word = w[i];
    const bool negation = word == "not" || word == "never" ||
                          (word == "no" && i + 1 < w.size() && polarity_of(w[i + 1]) != 0);
    if (negation) {
      negation_at = i;
      continue;
    }
    int p = polarity_of(word);
    if (p == 0) {
      if (!harmless(word)) return Builtin::kNone;
      continue;
    }
    if (negation_at < i && i - negation_at <= 2) {
      p = -p;
      negation_at = w.size();
    }
    if (sign != 0 && p != sign) return Builtin::kNone;
    sign = p;
  }
  if (sign == 0 && negation_at < w.size()) {
    for (std::size_t i = 0; i < negation_at; ++i) {
      if (w[i] == "rather" || w[i] == "prefer") negated_wish = true;
    }
    if (negated_wish) return Builtin::kNo;
  }
  if (sign > 0) return Builtin::kYes;
  if (sign < 0) return Builtin::kNo;
  return Builtin::kNone;
}

}  // namespace

Builtin classify_builtin(std::string_view utterance) {
  std::vector<std::string> words = normalize(utterance);
  std::size_t begin = 0, end = words.size();
  if (end - begin >= 2 && (words[0] == "hey" || words[0] == "ok" || words[0] == "okay") &&
      words[1] == "marvin") {
    begin = 2;
  } else if (end - begin >= 1 && words[0] == "marvin") {
    begin = 1;
  }
  std::string text = join_words(words, begin, end);
  for (const Phrase& phrase : kPhrases) {
    if (phrase.text == text) return phrase.meaning;
  }
  // Politeness around the phrase: "please stop", "cancel please".
  if (end - begin >= 2 && words[begin] == "please") ++begin;
  if (end - begin >= 2 && words[end - 1] == "please") --end;
  text = join_words(words, begin, end);
  for (const Phrase& phrase : kPhrases) {
    if (phrase.text == text) return phrase.meaning;
  }
  // People say more than the bare word: "hey, could you stop that now", "yes that is right".
  std::vector<std::string> request =
      strip_politeness(std::vector<std::string>(words.begin() + static_cast<std::ptrdiff_t>(begin),
                                                words.begin() + static_cast<std::ptrdiff_t>(end)));
  text = join_words(request, 0, request.size());
  for (const Phrase& phrase : kPhrases) {
    if (phrase.text == text) return phrase.meaning;
  }
  if (Builtin b = by_head_word(request); b != Builtin::kNone) return b;
  if (Builtin b = by_head_word_after_lead_in(request); b != Builtin::kNone) return b;
  return by_polarity(request);
}

}  // namespace marvin::interpret
