#include "perception/kws/keyword_spotter.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "perception/kws/features.h"

namespace marvin::perception::kws {

DetectionDecider::DetectionDecider(int smoothing_windows, float threshold, int refractory_windows)
    : history_(static_cast<std::size_t>(std::max(1, smoothing_windows)), 0.0f),
      threshold_(threshold),
      refractory_windows_(std::max(0, refractory_windows)),
      since_fire_(refractory_windows_ + 1) {}

bool DetectionDecider::push(float keyword_posterior) {
  history_[next_] = keyword_posterior;
  next_ = (next_ + 1) % history_.size();
  count_ = std::min(count_ + 1, history_.size());
  float sum = 0.0f;
  for (float v : history_) sum += v;
  smoothed_ = sum / static_cast<float>(history_.size());
  ++since_fire_;
  if (smoothed_ >= threshold_ && since_fire_ > refractory_windows_) {
    since_fire_ = 0;
    return true;
  }
  return false;
}

void DetectionDecider::reset() {
  std::fill(history_.begin(), history_.end(), 0.0f);
  next_ = 0;
  count_ = 0;
  since_fire_ = refractory_windows_ + 1;
  smoothed_ = 0.0f;
}

int refractory_windows(const KwsModel& model) {
  const double hop_s = model.features.hop_frames * model.features.log_mel.hop_ms / 1000.0;
  return static_cast<int>(std::ceil(model.detection.refractory_seconds / hop_s - 1e-6));
}

KeywordSpotter::KeywordSpotter(const KwsModel& model, Precision precision)
    : norm_(model.normalisation),
      hop_frames_(model.features.hop_frames),
      hop_samples_(model.features.log_mel.sample_rate * model.features.log_mel.hop_ms / 1000),
      window_samples_(model.features.log_mel.sample_rate * model.features.log_mel.window_ms / 1000),
      precision_(precision),
      decider_(model.detection.smoothing_windows, model.detection.threshold,
               refractory_windows(model)),
      ring_(static_cast<std::size_t>(kWindowFrames * kBins)),
      window_(static_cast<std::size_t>(kWindowFrames * kBins)),
      input_(static_cast<std::size_t>(kInputSize)) {
  if (precision == Precision::int8) {
    int8_net_ = std::make_unique<Int8Inference>(model.int8_network());
  } else {
    float_net_ = std::make_unique<FloatInference>(model.network);
  }
}

KeywordSpotter::~KeywordSpotter() = default;

void KeywordSpotter::set_int8_kernel(Int8Kernel kernel) {
  if (!int8_net_) {
    throw std::logic_error(std::string("kws KeywordSpotter: the ") + kernel_name(kernel) +
                           " kernel is int8, but this spotter runs in float");
  }
  int8_net_->set_kernel(kernel);
}

void KeywordSpotter::reset() {
  decider_.reset();
  next_frame_ = 0;
  stored_ = 0;
  windows_run_ = 0;
}

void KeywordSpotter::classify_window(std::span<const float> frames,
                                     std::span<float> probabilities) {
  window_to_input(frames, norm_, input_);
  if (int8_net_) {
    int8_net_->run(input_, probabilities);
  } else {
    float_net_->run(input_, probabilities);
  }
}

std::size_t KeywordSpotter::push_frames(std::span<const float> frames, std::int64_t first_frame,
                                        std::vector<WakeWordDetection>& detections) {
  if (frames.size() % kBins != 0) {
    throw std::invalid_argument("KeywordSpotter::push_frames: " + std::to_string(frames.size()) +
                                " values is not a whole number of 40-bin frames");
  }
  if (first_frame != next_frame_) {
    decider_.reset();
    stored_ = 0;
  }
  std::size_t appended = 0;
  const std::size_t n = frames.size() / kBins;
  for (std::size_t i = 0; i < n; ++i) {
    const std::int64_t index = first_frame + static_cast<std::int64_t>(i);
    const std::size_t slot = static_cast<std::size_t>(index % kWindowFrames);
    std::copy_n(frames.begin() + static_cast<std::ptrdiff_t>(i * kBins), kBins,
                ring_.begin() + static_cast<std::ptrdiff_t>(slot * kBins));
    stored_ = std::min<std::int64_t>(stored_ + 1, kWindowFrames);
    const std::int64_t end = index + 1;
    if (stored_ == kWindowFrames && (end - kWindowFrames) % hop_frames_ == 0) {
      run_window(end, detections, appended);
    }
  }
  next_frame_ = first_frame + static_cast<std::int64_t>(n);
  return appended;
}

void KeywordSpotter::run_window(std::int64_t end_frame, std::vector<WakeWordDetection>& detections,
                                std::size_t& appended) {
  const std::int64_t begin_frame = end_frame - kWindowFrames;
  for (int k = 0; k < kWindowFrames; ++k) {
    const std::size_t slot = static_cast<std::size_t>((begin_frame + k) % kWindowFrames);
    std::copy_n(ring_.begin() + static_cast<std::ptrdiff_t>(slot * kBins), kBins,
                window_.begin() + static_cast<std::ptrdiff_t>(k) * kBins);
  }
  float probs[kClasses];
  classify_window(window_, probs);
  ++windows_run_;
  const bool fire = decider_.push(probs[0]);
  if (observer_) observer_(observer_context_, end_frame, probs[0], decider_.smoothed());
  if (fire) {
    WakeWordDetection d;
    d.begin_sample = begin_frame * hop_samples_;
    d.end_sample = (end_frame - 1) * hop_samples_ + window_samples_;
    d.score = decider_.smoothed();
    detections.push_back(d);
    ++appended;
  }
}

}  // namespace marvin::perception::kws
