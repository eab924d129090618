// Sound held in memory: interleaved float samples in [-1, 1] with their rate and channels.
//
// The speech path works on 16 kHz mono 16-bit PCM (pocketsphinx, espeak-ng and the log-mel
// features all use it); SoundBuffer is the general form read from and written to files.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace marvin::audio {

// The sample rate of the speech path (features, wake word, recognition, synthesis).
inline constexpr int kSpeechSampleRate = 16000;

struct SoundBuffer {
  int sample_rate = kSpeechSampleRate;
  int channels = 1;
  std::vector<float> samples;  // interleaved, channels * frames values

  std::size_t frames() const { return channels > 0 ? samples.size() / channels : 0; }
  double seconds() const {
    return sample_rate > 0 ? static_cast<double>(frames()) / sample_rate : 0.0;
  }
};

// float [-1, 1] -> int16 with rounding and clipping, and back. Sizes must match.
void float_to_pcm16(std::span<const float> in, std::span<std::int16_t> out);
void pcm16_to_float(std::span<const std::int16_t> in, std::span<float> out);

std::vector<std::int16_t> to_pcm16(std::span<const float> in);
std::vector<float> to_float(std::span<const std::int16_t> in);

}  // namespace marvin::audio
