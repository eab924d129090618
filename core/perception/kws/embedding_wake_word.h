// The embedding wake word (issue 21): openWakeWord's approach in Marvin's code. A frozen speech
// embedding learned by Google from large amounts of real speech (speech_embedding.h) turns
// every 80 ms of audio into 96 numbers; a small head trained here on synthetic speech
// (embedding_head.h) scores the last 16 of them.
//
// Detection: the head's score every 80 ms (after 1.28 s of audio), a threshold that a number
// of consecutive scores must reach, and a refractory period (the head's defaults).
// Sensitivity s in [0, 1] maps to the threshold piecewise linearly: 0 -> 0.99, 0.5 -> the
// head's own threshold, 1 -> 0.05.
//
// Where the keyword ended (WakeWordDetection::end_sample, where the command starts): the head
// is sure before the word is over (already during "-vin"), and a high threshold makes the
// detection itself come late, in the command. The end is placed where the scores first
// reached kKeywordEndScore (or the threshold, if lower) the head's consecutive number of times
// in the run that led to the detection: the shipped head's detection point when the voice
// loop and its tests were tuned (threshold 0.8, 4 steps), whatever the sensitivity.
//
// Thread safety: none (one detector per stream).
#pragma once

#include <deque>
#include <filesystem>
#include <memory>
#include <string>

#include "perception/kws/embedding_head.h"
#include "perception/kws/speech_embedding.h"
#include "perception/wake_word_detector.h"

namespace marvin::perception::kws {

inline constexpr float kKeywordEndScore = 0.8f;

struct EmbeddingWakeWordOptions {
  std::filesystem::path model_dir = embedding_model_dir();  // the two ONNX files
  std::filesystem::path head_path = default_head_path();
  float sensitivity = 0.5f;
};

class EmbeddingWakeWord : public WakeWordDetector {
 public:
  // Loads the models; throws std::runtime_error naming a missing ONNX file and scripts/setup,
  // OnnxError for a damaged one, ModelFileError for a bad head.
  explicit EmbeddingWakeWord(const EmbeddingWakeWordOptions& options = {});
  EmbeddingWakeWord(std::shared_ptr<const EmbeddingModels> models, EmbeddingHead head,
                    float sensitivity);

  const std::string& keyword() const override { return head_.keyword; }
  void set_sensitivity(float sensitivity) override;
  float sensitivity() const override { return sensitivity_; }
  std::size_t process(std::span<const std::int16_t> samples,
                      std::vector<WakeWordDetection>& detections) override;
  void reset() override;

  float threshold_for(float sensitivity) const;
  // Every head score so far with the sample where its audio ends (for evaluation tools).
  void set_score_log(std::vector<std::pair<std::int64_t, float>>* log) { score_log_ = log; }
  // Scores audio in float [-1, 1] (the training tools' format); same as process().
  std::size_t process_float(std::span<const float> samples,
                            std::vector<WakeWordDetection>& detections);

 private:
  std::size_t consume(std::vector<WakeWordDetection>& detections);

  std::shared_ptr<const EmbeddingModels> models_;
  EmbeddingHead head_;
  EmbeddingStream stream_;
  float sensitivity_ = 0.5f;
  float threshold_ = 0.5f;
  std::deque<Embedding> history_;
  std::vector<Embedding> fresh_;
  std::vector<float> input_;
  std::vector<float> scaled_;
  std::int64_t last_detection_end_ = -1;
  int run_ = 0;  // consecutive scores at or over the threshold so far
  int end_run_ = 0;  // consecutive scores at or over min(kKeywordEndScore, threshold_)
  std::int64_t keyword_end_ = -1;  // where end_run_ reached the head's count in this run
  std::vector<std::pair<std::int64_t, float>>* score_log_ = nullptr;
};

}  // namespace marvin::perception::kws
