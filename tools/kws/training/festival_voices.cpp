#include "kws/training/festival_voices.h"

#include <algorithm>
#include <cctype>
#include <stdexcept>
#include <string>

#include "kws/training/synthesiser_program.h"

namespace marvin::perception::kws {

const std::vector<std::string>& festival_voices() {
  static const std::vector<std::string> voices = {"kal_diphone",       "cmu_us_slt_arctic_hts",
                                                  "czech_dita",        "czech_machac",
                                                  "suo_fi_lj_diphone", "upc_ca_ona_hts"};
  return voices;
}

const std::vector<std::string>& festival_heldout_voices() {
  static const std::vector<std::string> voices = {"ked_diphone", "czech_krb", "czech_ph",
                                                  "hy_fi_mv_diphone"};
  return voices;
}

std::vector<float> synthesize_festival(const std::string& text, const std::string& voice,
                                       float stretch) {
  // The name goes into a Scheme expression: letters, digits and underscores only.
  if (voice.empty() || !std::all_of(voice.begin(), voice.end(), [](unsigned char c) {
        return std::isalnum(c) != 0 || c == '_';
      })) {
    throw std::runtime_error("festival voice \"" + voice +
                             "\": expected a voice name such as kal_diphone");
  }
  // text2wave reads the text from its standard input when given no file.
  return run_synthesiser(
      {"text2wave", "-eval", "(voice_" + voice + ")", "-eval",
       "(Parameter.set 'Duration_Stretch " + std::to_string(stretch) + ")", "-F", "16000", "-otype",
       "riff", "-o", "{out}"},
      "festival, the training tools' third synthesiser",
      "festival voice \"" + voice + "\" said nothing for \"" + text +
          "\" (an unknown voice, or its festvox package is missing: run scripts/setup)",
      text + "\n");
}

}  // namespace marvin::perception::kws
