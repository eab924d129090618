// Sample-rate conversion (libsoxr) and channel mixing.
#pragma once

#include <cstddef>
#include <memory>
#include <span>
#include <vector>

#include "devices/audio/sound_buffer.h"

namespace marvin::audio {

// Averages the channels of interleaved samples into one.
std::vector<float> mix_to_mono(std::span<const float> interleaved, int channels);

// Converts a whole mono signal from `from_rate` to `to_rate` (high quality, linear phase).
// Returns the input unchanged when the rates are equal. Throws std::runtime_error on a
// non-positive rate.
std::vector<float> resample(std::span<const float> mono, int from_rate, int to_rate);

// Any SoundBuffer -> the 16 kHz mono speech format, as floats.
std::vector<float> to_speech_format(const SoundBuffer& sound);

// Streaming conversion of a mono signal, for live capture at the card's native rate.
// process() may be called with chunks of any size; output lags the input by the filter
// delay; flush() returns the tail. Not thread-safe; one stream per object.
class StreamResampler {
 public:
  StreamResampler(int from_rate, int to_rate);
  ~StreamResampler();
  StreamResampler(const StreamResampler&) = delete;
  StreamResampler& operator=(const StreamResampler&) = delete;

  // Appends the converted samples for `in` to `out`.
  void process(std::span<const float> in, std::vector<float>& out);
  // Appends what is still buffered in the filter to `out`; the stream then ends.
  void flush(std::vector<float>& out);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace marvin::audio
