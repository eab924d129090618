// End-of-speech detection from silence, for the command that follows the wake word.
//
// Works on 10 ms frames of 16 kHz PCM16. A frame is speech when its energy (dBFS) exceeds
// both `min_speech_db` and the running noise floor + `margin_db`. Speech has started after
// `speech_start_ms` of speech frames in a row; it has ended after `trailing_silence_ms` of
// non-speech frames following speech. A listener who never speaks times out after
// `no_speech_timeout_ms`; one who never stops is cut after `max_speech_ms`.
//
// Decision: the trailing silence is the main cost in the reply delay (the user waits for it
// after their last word). 250 ms: bench/voice_loop measured end of speech -> first reply
// sample at median 261 ms (max 307 ms) against 420 ms with the former 400 ms, at the same
// sentence accuracy on espeak-ng speech (13/15; out-of-grammar rejection 4/4 against 3/4),
// meeting the < 300 ms goal. Slow speakers who pause longer than that between words are
// cut; raise it for them (the bench shows what each setting costs).
#pragma once

#include <array>
#include <cstdint>
#include <span>

namespace marvin::perception {

struct EndpointerOptions {
  int sample_rate = 16000;
  float min_speech_db = -50.0f;  // absolute floor: quieter frames are never speech
  float margin_db = 12.0f;       // above the noise floor
  int speech_start_ms = 50;
  int trailing_silence_ms = 250;
  int no_speech_timeout_ms = 5000;
  int max_speech_ms = 10000;
};

enum class EndpointState {
  kWaitingForSpeech,  // nothing said yet
  kInSpeech,          // speech started, not yet ended
  kEnded,             // speech ended (trailing silence seen) or was cut at max_speech_ms
  kTimedOut,          // no speech within no_speech_timeout_ms
};

const char* to_string(EndpointState state);

class Endpointer {
 public:
  explicit Endpointer(const EndpointerOptions& options = {});

  // Consumes samples and returns the state after them. Once kEnded or kTimedOut, further
  // samples are ignored until reset(). Allocation-free.
  EndpointState push(std::span<const std::int16_t> samples);

  EndpointState state() const { return state_; }
  // Samples consumed since reset() up to the decision (all of them while undecided).
  std::int64_t samples_seen() const { return samples_seen_; }
  // First and one-past-last sample of detected speech (valid once speech started).
  std::int64_t speech_begin() const { return speech_begin_; }
  std::int64_t speech_end() const { return speech_end_; }

  void reset();

 private:
  void on_frame(float energy_db);

  EndpointerOptions options_;
  int frame_samples_;
  std::array<std::int16_t, 480> frame_{};  // up to 10 ms at 48 kHz
  int filled_ = 0;
  EndpointState state_ = EndpointState::kWaitingForSpeech;
  std::int64_t samples_seen_ = 0;
  std::int64_t speech_begin_ = 0;
  std::int64_t speech_end_ = 0;
  float noise_db_ = -90.0f;
  int speech_run_ = 0;
  int silence_run_ = 0;
  int frames_total_ = 0;
  int frames_in_speech_ = 0;
};

}  // namespace marvin::perception
