#include "kws/training/flite_voices.h"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "kws/training/synthesiser_program.h"

namespace marvin::perception::kws {

const std::vector<std::string>& flite_voices() {
  static const std::vector<std::string> voices = {"kal16", "awb", "rms", "slt"};
  return voices;
}

std::vector<float> synthesize_flite(const std::string& text, const std::string& voice,
                                    float stretch, float f0_hz) {
  const auto& known = flite_voices();
  if (std::find(known.begin(), known.end(), voice) == known.end()) {
    // flite itself falls back to its default voice without a word: refuse here instead.
    throw std::runtime_error("flite voice \"" + voice + "\": expected one of kal16, awb, rms, slt");
  }
  return run_synthesiser(
      {"flite", "-voice", voice, "--setf", "duration_stretch=" + std::to_string(stretch), "--setf",
       "int_f0_target_mean=" + std::to_string(f0_hz), "-t", text, "-o", "{out}"},
      "the training tools' second synthesiser",
      "flite -voice " + voice + " failed on \"" + text + "\"");
}

}  // namespace marvin::perception::kws
