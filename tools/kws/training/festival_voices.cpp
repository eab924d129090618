#include "kws/training/festival_voices.h"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <filesystem>
#include <fstream>
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

std::vector<float> synthesize_festival(const std::string& text, const std::string& voice,
                                       float stretch) {
  // The name goes into a Scheme expression: letters, digits and underscores only.
  if (voice.empty() || !std::all_of(voice.begin(), voice.end(), [](unsigned char c) {
        return std::isalnum(c) != 0 || c == '_';
      })) {
    throw std::runtime_error("festival voice \"" + voice +
                             "\": expected a voice name such as kal_diphone");
  }
  // text2wave reads the text from a file; one per call, like the sound it writes.
  static std::atomic<int> counter{0};
  const std::filesystem::path text_file =
      std::filesystem::temp_directory_path() /
      ("marvin-festival-" + std::to_string(getpid()) + "-" + std::to_string(counter++) + ".txt");
  std::ofstream(text_file) << text << "\n";
  std::vector<float> sound;
  try {
    sound = run_synthesiser(
        {"text2wave", "-eval", "(voice_" + voice + ")", "-eval",
         "(Parameter.set 'Duration_Stretch " + std::to_string(stretch) + ")", "-F", "16000",
         "-otype", "riff", "-o", "{out}", text_file.string()},
        "festival, the training tools' third synthesiser",
        "festival voice \"" + voice + "\" said nothing for \"" + text +
            "\" (an unknown voice, or its festvox package is missing: run scripts/setup)");
  } catch (...) {
    std::filesystem::remove(text_file);
    throw;
  }
  std::filesystem::remove(text_file);
  return sound;
}

}  // namespace marvin::perception::kws
