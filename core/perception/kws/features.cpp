#include "perception/kws/features.h"

#include <algorithm>
#include <stdexcept>

namespace marvin::perception::kws {

void window_to_input(std::span<const float> frames, const Normalisation& norm,
                     std::span<float> input) {
  if (frames.size() != static_cast<std::size_t>(kWindowFrames * kBins) ||
      input.size() != static_cast<std::size_t>(kInputSize)) {
    throw std::invalid_argument("kws window_to_input: needs 96x40 frames and a 32x40 input");
  }
  constexpr float third = 1.0f / static_cast<float>(kFramesPerInput);
  for (int t = 0; t < kInputFrames; ++t) {
    const float* f0 = frames.data() + t * kFramesPerInput * kBins;
    float* out = input.data() + t * kBins;
    for (int b = 0; b < kBins; ++b) {
      float sum = 0.0f;
      for (int k = 0; k < kFramesPerInput; ++k) sum += f0[k * kBins + b];
      out[b] = (sum * third - norm.mean[static_cast<std::size_t>(b)]) * norm.inv_std;
    }
  }
}

void clip_frames(LogMelExtractor& extractor, std::span<const std::int16_t> clip,
                 std::vector<float>& frames) {
  frames.clear();
  frames.reserve(static_cast<std::size_t>(kWindowFrames * kBins));
  extractor.reset();
  std::size_t need = static_cast<std::size_t>(kWindowSamples);
  auto on_frame = [&](std::span<const float> bins) {
    if (frames.size() < static_cast<std::size_t>(kWindowFrames * kBins)) {
      frames.insert(frames.end(), bins.begin(), bins.end());
    }
  };
  const std::size_t take = std::min(clip.size(), need);
  extractor.push(clip.subspan(0, take), on_frame);
  if (take < need) {
    static const std::vector<std::int16_t> zeros(static_cast<std::size_t>(kWindowSamples), 0);
    extractor.push(std::span<const std::int16_t>(zeros).subspan(0, need - take), on_frame);
  }
  extractor.reset();
}

}  // namespace marvin::perception::kws
