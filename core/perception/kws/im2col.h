// Internal: the im2col layouts shared by inference (network.cpp) and training (trainer.cpp).
#pragma once

#include <cstring>

#include "perception/kws/network.h"

namespace marvin::perception::kws::detail {

// Conv1 im2col: one row per output position (t, f), kConv1In columns (dt*8+df).
template <typename T>
inline void im2col_conv1(const T* input, T* cols) {
  for (int t = 0; t < kConv1OutTime; ++t) {
    for (int f = 0; f < kConv1OutFreq; ++f) {
      T* row = cols + (t * kConv1OutFreq + f) * kConv1In;
      for (int dt = 0; dt < kConv1Time; ++dt) {
        std::memcpy(row + dt * kConv1Freq, input + (t + dt) * kBins + f,
                    sizeof(T) * kConv1Freq);
      }
    }
  }
}

// Conv2 im2col from a1[t][f][c]: one row per output position, (dt*4+df)*64+ic columns; the
// four frequencies of one dt are contiguous in a1, so each dt is one copy.
template <typename T>
inline void im2col_conv2(const T* a1, T* cols) {
  constexpr int span = kConv2Freq * kConv1Maps;
  for (int t = 0; t < kConv2OutTime; ++t) {
    for (int f = 0; f < kConv2OutFreq; ++f) {
      T* row = cols + (t * kConv2OutFreq + f) * kConv2In;
      for (int dt = 0; dt < kConv2Time; ++dt) {
        std::memcpy(row + dt * span, a1 + ((t + dt) * kPooledFreq + f) * kConv1Maps,
                    sizeof(T) * span);
      }
    }
  }
}

}  // namespace marvin::perception::kws::detail
