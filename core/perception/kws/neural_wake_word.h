// The neural wake-word detector: cnn-trad-fpool3 (network.h) behind WakeWordDetector, so the
// voice loop can use it in place of pocketsphinx keyphrase spotting.
//
// It works on log-mel frames (wants_features() is true): give it process_features() with the
// voice loop's LogMelExtractor frames, or raw audio through process(), which runs its own
// extractor. Use one or the other on a stream, not both.
//
// Sensitivity s in [0, 1] maps to the threshold on the smoothed keyword posterior, piecewise
// linearly: 0 -> 0.99, 0.5 -> the model's own threshold, 1 -> 0.05.
//
// Thread safety: none (one detector per stream, as the interface says).
#pragma once

#include <filesystem>
#include <memory>
#include <string>

#include "perception/kws/keyword_spotter.h"
#include "perception/log_mel.h"
#include "perception/wake_word_detector.h"

namespace marvin::perception::kws {

// The model the build ships: $MARVIN_KWS_MODEL if set, else models/marvin-kws.bin of the
// source tree this library was built from.
std::filesystem::path default_model_path();

struct NeuralWakeWordOptions {
  std::filesystem::path model_path = default_model_path();
  float sensitivity = 0.5f;
  Precision precision = Precision::int8;
};

class NeuralWakeWord : public WakeWordDetector {
 public:
  // Loads the model; throws ModelFileError (see model_file.h) when it is missing or bad.
  explicit NeuralWakeWord(const NeuralWakeWordOptions& options = {});
  // Uses an already loaded model.
  NeuralWakeWord(const KwsModel& model, float sensitivity, Precision precision);
  ~NeuralWakeWord() override;

  const std::string& keyword() const override { return keyword_; }
  void set_sensitivity(float sensitivity) override;
  float sensitivity() const override { return sensitivity_; }
  std::size_t process(std::span<const std::int16_t> samples,
                      std::vector<WakeWordDetection>& detections) override;
  bool wants_features() const override { return true; }
  std::size_t process_features(std::span<const float> frames, std::int64_t first_frame,
                               std::vector<WakeWordDetection>& detections) override;
  void reset() override;

  // The posterior threshold a sensitivity maps to for this model.
  float threshold_for(float sensitivity) const;
  KeywordSpotter& spotter() { return *spotter_; }

 private:
  std::string keyword_;
  float model_threshold_;
  float sensitivity_ = 0.5f;
  std::unique_ptr<KeywordSpotter> spotter_;
  LogMelExtractor extractor_;
  std::int64_t frames_seen_ = 0;
};

}  // namespace marvin::perception::kws
