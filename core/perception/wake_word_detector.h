// The wake word: the word that makes the robot listen ("marvin").
//
// A WakeWordDetector watches a continuous 16 kHz mono stream and reports each time the
// keyword was spoken. Implementations: PocketsphinxWakeWord (keyphrase spotting, this
// folder) and the neural spotter of issue 9, which works on log-mel frames (log_mel.h) and
// says so through wants_features().
//
// Time: sample indices count every sample given to process() since construction or the
// last reset(); for a detector fed features, frame f covers samples [f*hop, f*hop+window).
//
// Thread safety: none; one detector is driven by one thread (the wake-word node).
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace marvin::perception {

struct WakeWordDetection {
  std::int64_t begin_sample = 0;  // best estimate of where the keyword began
  std::int64_t end_sample = 0;    // where it ended: the command starts after this sample
  float score = 0.0f;             // detector's confidence; higher is surer; scale is per detector
};

class WakeWordDetector {
 public:
  virtual ~WakeWordDetector() = default;

  // The keyword, in lower case ("marvin").
  virtual const std::string& keyword() const = 0;

  // Sensitivity in [0, 1]: 0 accepts the fewest false alarms, 1 misses the fewest keywords.
  // Values outside are clamped. Takes effect for the audio given afterwards.
  virtual void set_sensitivity(float sensitivity) = 0;
  virtual float sensitivity() const = 0;

  // Feeds 16 kHz mono PCM16 of any length and appends a detection to `detections` for each
  // keyword that ended inside it (usually none). Returns the number appended.
  virtual std::size_t process(std::span<const std::int16_t> samples,
                              std::vector<WakeWordDetection>& detections) = 0;

  // Detectors working on log-mel frames say true and accept process_features(): `frames`
  // holds whole frames (LogMelOptions defaults, num_bins values each), the first being
  // frame `first_frame` of the stream. The default implementation throws std::logic_error.
  virtual bool wants_features() const { return false; }
  virtual std::size_t process_features(std::span<const float> frames, std::int64_t first_frame,
                                       std::vector<WakeWordDetection>& detections);

  // Forgets all history; sample numbering restarts at 0.
  virtual void reset() = 0;
};

}  // namespace marvin::perception
