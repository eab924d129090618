#include "interpret/builtins.h"

#include <array>
#include <string>
#include <utility>
#include <vector>

#include "interpret/normalizer.h"

namespace marvin::interpret {
namespace {

struct Phrase {
  std::string_view text;
  Builtin meaning;
};

// Normalised forms ("one" would be "1"; none of these contain number words).
constexpr std::array kPhrases{
    Phrase{"stop", Builtin::kStop},           Phrase{"cancel", Builtin::kStop},
    Phrase{"never mind", Builtin::kStop},     Phrase{"nevermind", Builtin::kStop},
    Phrase{"stop it", Builtin::kStop},        Phrase{"stop that", Builtin::kStop},
    Phrase{"cancel that", Builtin::kStop},    Phrase{"cancel it", Builtin::kStop},
    Phrase{"abort", Builtin::kStop},          Phrase{"halt", Builtin::kStop},
    Phrase{"quiet", Builtin::kStop},          Phrase{"be quiet", Builtin::kStop},
    Phrase{"shut up", Builtin::kStop},        Phrase{"enough", Builtin::kStop},
    Phrase{"that's enough", Builtin::kStop},  Phrase{"forget it", Builtin::kStop},
    Phrase{"stop stop", Builtin::kStop},      Phrase{"yes", Builtin::kYes},
    Phrase{"yeah", Builtin::kYes},            Phrase{"yep", Builtin::kYes},
    Phrase{"yup", Builtin::kYes},             Phrase{"sure", Builtin::kYes},
    Phrase{"ok", Builtin::kYes},              Phrase{"okay", Builtin::kYes},
    Phrase{"of course", Builtin::kYes},       Phrase{"yes please", Builtin::kYes},
    Phrase{"correct", Builtin::kYes},         Phrase{"right", Builtin::kYes},
    Phrase{"do it", Builtin::kYes},           Phrase{"go ahead", Builtin::kYes},
    Phrase{"absolutely", Builtin::kYes},      Phrase{"affirmative", Builtin::kYes},
    Phrase{"that's right", Builtin::kYes},    Phrase{"please do", Builtin::kYes},
    Phrase{"yes do it", Builtin::kYes},       Phrase{"no", Builtin::kNo},
    Phrase{"nope", Builtin::kNo},             Phrase{"nah", Builtin::kNo},
    Phrase{"no thanks", Builtin::kNo},        Phrase{"no thank you", Builtin::kNo},
    Phrase{"don't", Builtin::kNo},            Phrase{"do not", Builtin::kNo},
    Phrase{"negative", Builtin::kNo},         Phrase{"not now", Builtin::kNo},
    Phrase{"no don't", Builtin::kNo},         Phrase{"repeat", Builtin::kRepeat},
    Phrase{"repeat that", Builtin::kRepeat},  Phrase{"say that again", Builtin::kRepeat},
    Phrase{"say it again", Builtin::kRepeat}, Phrase{"again", Builtin::kRepeat},
    Phrase{"pardon", Builtin::kRepeat},       Phrase{"what did you say", Builtin::kRepeat},
    Phrase{"come again", Builtin::kRepeat},   Phrase{"sorry what", Builtin::kRepeat},
    Phrase{"repeat please", Builtin::kRepeat},
};

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
  return Builtin::kNone;
}

}  // namespace marvin::interpret
