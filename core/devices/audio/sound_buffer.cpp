#include "devices/audio/sound_buffer.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace marvin::audio {

void float_to_pcm16(std::span<const float> in, std::span<std::int16_t> out) {
  if (in.size() != out.size()) throw std::runtime_error("float_to_pcm16: sizes differ");
  for (std::size_t i = 0; i < in.size(); ++i) {
    const float scaled = std::clamp(in[i] * 32768.0f, -32768.0f, 32767.0f);
    out[i] = static_cast<std::int16_t>(std::lrint(scaled));
  }
}

void pcm16_to_float(std::span<const std::int16_t> in, std::span<float> out) {
  if (in.size() != out.size()) throw std::runtime_error("pcm16_to_float: sizes differ");
  for (std::size_t i = 0; i < in.size(); ++i) out[i] = static_cast<float>(in[i]) / 32768.0f;
}

std::vector<std::int16_t> to_pcm16(std::span<const float> in) {
  std::vector<std::int16_t> out(in.size());
  float_to_pcm16(in, out);
  return out;
}

std::vector<float> to_float(std::span<const std::int16_t> in) {
  std::vector<float> out(in.size());
  pcm16_to_float(in, out);
  return out;
}

}  // namespace marvin::audio
