#include "perception/kws/embedding_wake_word.h"

#include <algorithm>

namespace marvin::perception::kws {

EmbeddingWakeWord::EmbeddingWakeWord(const EmbeddingWakeWordOptions& options)
    : EmbeddingWakeWord(EmbeddingModels::load(options.model_dir), load_head(options.head_path),
                        options.sensitivity) {}

EmbeddingWakeWord::EmbeddingWakeWord(std::shared_ptr<const EmbeddingModels> models,
                                     EmbeddingHead head, float sensitivity)
    : models_(std::move(models)), head_(std::move(head)), stream_(models_) {
  input_.resize(kHeadInputs);
  set_sensitivity(sensitivity);
}

float EmbeddingWakeWord::threshold_for(float sensitivity) const {
  const float s = std::clamp(sensitivity, 0.0f, 1.0f);
  const float mid = head_.threshold;
  return s <= 0.5f ? 0.99f + (mid - 0.99f) * (s / 0.5f) : mid + (0.05f - mid) * ((s - 0.5f) / 0.5f);
}

void EmbeddingWakeWord::set_sensitivity(float sensitivity) {
  sensitivity_ = std::clamp(sensitivity, 0.0f, 1.0f);
  threshold_ = threshold_for(sensitivity_);
}

void EmbeddingWakeWord::reset() {
  stream_.reset();
  history_.clear();
  last_detection_end_ = -1;
  run_ = 0;
  end_run_ = 0;
  keyword_end_ = -1;
}

std::size_t EmbeddingWakeWord::process(std::span<const std::int16_t> samples,
                                       std::vector<WakeWordDetection>& detections) {
  scaled_.assign(samples.begin(), samples.end());
  fresh_.clear();
  stream_.push(scaled_, fresh_);
  return consume(detections);
}

std::size_t EmbeddingWakeWord::process_float(std::span<const float> samples,
                                             std::vector<WakeWordDetection>& detections) {
  scaled_.resize(samples.size());
  for (std::size_t k = 0; k < samples.size(); ++k) scaled_[k] = samples[k] * 32768.0f;
  fresh_.clear();
  stream_.push(scaled_, fresh_);
  return consume(detections);
}

std::size_t EmbeddingWakeWord::consume(std::vector<WakeWordDetection>& detections) {
  std::size_t added = 0;
  // The stream has produced fresh_.size() embeddings; the k-th ends at this sample.
  const std::int64_t last_end = stream_.samples_seen();
  for (std::size_t k = 0; k < fresh_.size(); ++k) {
    history_.push_back(fresh_[k]);
    if (history_.size() > static_cast<std::size_t>(kHeadEmbeddings)) history_.pop_front();
    if (history_.size() < static_cast<std::size_t>(kHeadEmbeddings)) continue;
    for (std::size_t e = 0; e < history_.size(); ++e) {
      std::copy(history_[e].begin(), history_[e].end(),
                input_.begin() + static_cast<std::ptrdiff_t>(e * kEmbeddingSize));
    }
    const float score = head_.score(input_);
    const std::int64_t end =
        last_end - static_cast<std::int64_t>(fresh_.size() - 1 - k) * kEmbeddingHop;
    if (score_log_ != nullptr) score_log_->emplace_back(end, score);
    const auto refractory = static_cast<std::int64_t>(head_.refractory_seconds * 16000.0f);
    run_ = score >= threshold_ ? run_ + 1 : 0;
    end_run_ = score >= std::min(kKeywordEndScore, threshold_) ? end_run_ + 1 : 0;
    if (end_run_ == 0) keyword_end_ = -1;
    if (end_run_ == head_.consecutive) keyword_end_ = end;
    if (run_ >= head_.consecutive &&
        (last_detection_end_ < 0 || end - last_detection_end_ >= refractory)) {
      last_detection_end_ = end;
      // The lower level's run contains this one, so keyword_end_ is set and not after end;
      // unset again for a second detection in one run (a score high for over the refractory).
      const std::int64_t keyword_end = keyword_end_ >= 0 ? keyword_end_ : end;
      keyword_end_ = -1;
      // A spoken keyword is under a second.
      detections.push_back({std::max<std::int64_t>(0, keyword_end - 16000), keyword_end, score});
      ++added;
    }
  }
  return added;
}

}  // namespace marvin::perception::kws
