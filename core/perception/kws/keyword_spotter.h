// Streaming keyword spotting: log-mel frames in, detections out.
//
// Every `hop_frames` frames (250 ms) once 96 frames have arrived, the last 96 frames go
// through the network; the keyword posteriors of the last `smoothing_windows` windows are
// averaged; a detection fires when that average reaches the threshold, after which nothing
// fires for `refractory_seconds` (so one "marvin", seen by several overlapping windows,
// fires once).
//
// Steady state allocates nothing. Not thread-safe; one spotter per stream.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "perception/kws/model_file.h"
#include "perception/wake_word_detector.h"

namespace marvin::perception::kws {

// The decision part alone (smoothing, threshold, refractory period) on a sequence of
// per-window keyword posteriors, so an evaluation can replay one posterior trace at many
// thresholds.
class DetectionDecider {
 public:
  DetectionDecider(int smoothing_windows, float threshold, int refractory_windows);
  // Adds the posterior of the next window; returns true when a detection fires on it.
  bool push(float keyword_posterior);
  float smoothed() const { return smoothed_; }
  void set_threshold(float threshold) { threshold_ = threshold; }
  float threshold() const { return threshold_; }
  void reset();

 private:
  std::vector<float> history_;
  std::size_t next_ = 0;
  std::size_t count_ = 0;
  float threshold_;
  int refractory_windows_;
  int since_fire_;
  float smoothed_ = 0.0f;
};

// Windows a detection blocks after it: ceil(refractory_seconds / window hop).
int refractory_windows(const KwsModel& model);

enum class Precision { float32, int8 };

class KeywordSpotter {
 public:
  // Throws std::invalid_argument when `precision` is int8 and the model cannot run in int8.
  KeywordSpotter(const KwsModel& model, Precision precision);
  ~KeywordSpotter();

  // Consumes whole frames (num_bins values each); `first_frame` is the stream index of the
  // first (frames must be given in order without gaps; a gap restarts the window). Appends a
  // detection per keyword; returns how many.
  std::size_t push_frames(std::span<const float> frames, std::int64_t first_frame,
                          std::vector<WakeWordDetection>& detections);

  void set_threshold(float threshold) { decider_.set_threshold(threshold); }
  float threshold() const { return decider_.threshold(); }

  // Called with (window index, end frame, keyword posterior, smoothed) after every window,
  // for evaluation and debugging; empty by default.
  using WindowObserver = void (*)(void* context, std::int64_t end_frame, float posterior,
                                  float smoothed);
  void set_window_observer(WindowObserver observer, void* context) {
    observer_ = observer;
    observer_context_ = context;
  }

  std::int64_t windows_run() const { return windows_run_; }
  void reset();

  // Chooses the int8 kernel (the fastest the CPU has by default; all give the same results),
  // so a benchmark can measure what a CPU without it would spend. Throws std::invalid_argument
  // for a kernel this CPU lacks (Int8Inference::set_kernel), std::logic_error for a spotter
  // running in float.
  void set_int8_kernel(Int8Kernel kernel);

  // The network on one 96-frame window (posteriors of all 4 classes), bypassing the state.
  void classify_window(std::span<const float> frames, std::span<float> probabilities);

 private:
  void run_window(std::int64_t end_frame, std::vector<WakeWordDetection>& detections,
                  std::size_t& appended);

  Normalisation norm_;
  int hop_frames_;
  int hop_samples_;
  int window_samples_;
  Precision precision_;
  std::unique_ptr<FloatInference> float_net_;
  std::unique_ptr<Int8Inference> int8_net_;
  DetectionDecider decider_;
  std::vector<float> ring_;    // kWindowFrames frames, circular
  std::vector<float> window_;  // the window in order
  std::vector<float> input_;
  std::int64_t next_frame_ = 0;  // stream index of the next expected frame
  std::int64_t stored_ = 0;      // frames in the ring (up to kWindowFrames)
  std::int64_t windows_run_ = 0;
  WindowObserver observer_ = nullptr;
  void* observer_context_ = nullptr;
};

}  // namespace marvin::perception::kws
