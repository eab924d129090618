// A test clip of speech synthesised by espeak-ng: a second of quiet, the words at half of
// full scale, then `quiet_after` samples of quiet; `noise` > 0 adds faint white noise of that
// amplitude (seeded, so every run hears the same clip). 16 kHz mono.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "devices/audio/sound_buffer.h"
#include "kws/training/dataset.h"

namespace marvin::perception::kws::testing {

inline std::vector<std::int16_t> spoken_clip(const std::string& text, const std::string& voice,
                                             std::size_t quiet_after, float noise = 0.0f) {
  std::vector<float> a(16000, 0.0f);
  std::vector<float> s = synthesize(text, voice, 160, 50);
  float peak = 0.0f;
  for (float v : s) peak = std::max(peak, std::fabs(v));
  for (float& v : s) v *= 0.5f / peak;
  a.insert(a.end(), s.begin(), s.end());
  a.resize(a.size() + quiet_after, 0.0f);
  if (noise > 0.0f) {
    std::uint32_t state = 12345;
    for (float& v : a) {
      state = state * 1664525u + 1013904223u;
      v += noise * (static_cast<float>(state >> 8) / 16777216.0f - 0.5f);
    }
  }
  return marvin::audio::to_pcm16(a);
}

}  // namespace marvin::perception::kws::testing
