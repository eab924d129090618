// From log-mel frames to the network's input, the same way in training and at run time.
//
// A window is kWindowFrames (96) consecutive log-mel frames, oldest first, kBins values each.
// Every 3 consecutive frames are averaged (32 input frames), then each bin has the model's
// mean subtracted and is multiplied by its inverse standard deviation.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "perception/kws/model_file.h"
#include "perception/log_mel.h"

namespace marvin::perception::kws {

// `frames`: kWindowFrames * kBins values; `input`: kInputSize values.
void window_to_input(std::span<const float> frames, const Normalisation& norm,
                     std::span<float> input);

// Log-mel frames of a clip of exactly 15600 samples or more (only the first kWindowFrames
// frames are kept); a shorter clip is zero-padded. `frames` is resized to kWindowFrames*kBins.
void clip_frames(LogMelExtractor& extractor, std::span<const std::int16_t> clip,
                 std::vector<float>& frames);

// Samples a window needs: (kWindowFrames - 1) * hop + window = 15600 at 16 kHz.
inline constexpr int kWindowSamples = (kWindowFrames - 1) * 160 + 400;

}  // namespace marvin::perception::kws
