#include "perception/kws/neural_wake_word.h"

#include <algorithm>
#include <cstdlib>

namespace marvin::perception::kws {

std::filesystem::path default_model_path() {
  if (const char* env = std::getenv("MARVIN_KWS_MODEL"); env != nullptr && *env != '\0') {
    return env;
  }
  return MARVIN_KWS_DEFAULT_MODEL;
}

NeuralWakeWord::NeuralWakeWord(const NeuralWakeWordOptions& options)
    : NeuralWakeWord(load_model(options.model_path), options.sensitivity, options.precision) {}

NeuralWakeWord::NeuralWakeWord(const KwsModel& model, float sensitivity, Precision precision)
    : keyword_(model.keyword),
      model_threshold_(model.detection.threshold),
      spotter_(std::make_unique<KeywordSpotter>(model, precision)),
      extractor_(model.features.log_mel) {
  set_sensitivity(sensitivity);
}

NeuralWakeWord::~NeuralWakeWord() = default;

float NeuralWakeWord::threshold_for(float sensitivity) const {
  const float s = std::clamp(sensitivity, 0.0f, 1.0f);
  const float mid = std::clamp(model_threshold_, 0.05f, 0.99f);
  if (s <= 0.5f) return 0.99f + (mid - 0.99f) * (s / 0.5f);
  return mid + (0.05f - mid) * ((s - 0.5f) / 0.5f);
}

void NeuralWakeWord::set_sensitivity(float sensitivity) {
  sensitivity_ = std::clamp(sensitivity, 0.0f, 1.0f);
  spotter_->set_threshold(threshold_for(sensitivity_));
}

std::size_t NeuralWakeWord::process(std::span<const std::int16_t> samples,
                                    std::vector<WakeWordDetection>& detections) {
  std::size_t appended = 0;
  extractor_.push(samples, [&](std::span<const float> bins) {
    appended += spotter_->push_frames(bins, frames_seen_, detections);
    ++frames_seen_;
  });
  return appended;
}

std::size_t NeuralWakeWord::process_features(std::span<const float> frames,
                                             std::int64_t first_frame,
                                             std::vector<WakeWordDetection>& detections) {
  return spotter_->push_frames(frames, first_frame, detections);
}

void NeuralWakeWord::reset() {
  spotter_->reset();
  extractor_.reset();
  frames_seen_ = 0;
}

}  // namespace marvin::perception::kws
