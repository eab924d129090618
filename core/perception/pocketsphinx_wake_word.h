// Wake-word spotting with pocketsphinx's keyphrase search: the keyword's phones against a
// phone loop, firing when the keyword path beats the loop by the threshold.
//
// Sensitivity s in [0, 1] maps to the keyphrase threshold 10^(-60 s): 0 -> 1 (deaf),
// 0.5 -> 1e-30 (default: catches espeak-ng's "marvin" and ignores ordinary commands in the
// tests), 1 -> 1e-60 (eager: fires on words that merely sound alike).
#pragma once

#include <memory>
#include <string>

#include "perception/sphinx_model.h"
#include "perception/wake_word_detector.h"

namespace marvin::perception {

struct PocketsphinxWakeWordOptions {
  SphinxModel model;
  std::string keyword = "marvin";  // every word must be in the model's dictionary
  float sensitivity = 0.5f;
};

class PocketsphinxWakeWord : public WakeWordDetector {
 public:
  // Loads the model (~0.1 s). Throws std::runtime_error when the model is missing or a word
  // of the keyword is not in the dictionary.
  explicit PocketsphinxWakeWord(const PocketsphinxWakeWordOptions& options = {});
  ~PocketsphinxWakeWord() override;

  const std::string& keyword() const override;
  void set_sensitivity(float sensitivity) override;
  float sensitivity() const override;
  std::size_t process(std::span<const std::int16_t> samples,
                      std::vector<WakeWordDetection>& detections) override;
  void reset() override;

  // The keyphrase threshold used for a sensitivity.
  static double threshold_for(float sensitivity);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace marvin::perception
