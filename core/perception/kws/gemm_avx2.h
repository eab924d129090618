// Internal: the AVX2 int8 path of Int8Inference (gemm_avx2.cpp), for CPUs without AVX-512
// VNNI. The same plan as the VNNI path (gemm_avx512.h) on 256-bit vectors: weights packed once,
// when the network is loaded, so that one 32-byte load holds 8 output channels x one group of
// inputs; a broadcast group of activations times that vector lands in 8 int32 accumulators,
// one per output channel, with no horizontal reduction; the activations are read in place
// through a RowsView (im2col fused into the kernel). Each loaded activation group is used for
// 16 output channels and each loaded weight vector for several rows (register blocking).
//
// Two element types, both exact in int32:
//   int16 x int16, groups of 2 (vpmaddwd): any signed activations (the network's input, the
//   dense layers).
//   uint8 x int8, groups of 4 (vpmaddubsw, then vpmaddwd by 1 to sum the int16 pairs): twice
//   the multiply-adds per instruction, but vpmaddubsw saturates its int16 pair sums, so this
//   is exact only for activations in 0..127: 2 x 127 x 128 = 32512 <= 32767 for any int8
//   weight. conv2's input (after ReLU, clamped to 127) is such. conv1's input is signed: the
//   +128 shift of the VNNI path would make it 1..255 and the pairs could saturate, so conv1
//   stays on int16.
// Call only when gemm_s16_avx2_available().
#pragma once

#include <cstdint>
#include <vector>

#include "perception/kws/gemm_avx512.h"  // RowsView, shared by both paths

namespace marvin::perception::kws::detail {

// Weights packed for 8-lane vectors (PackedWeights in gemm_avx512.h).
template <typename W>
using PackedWeights256 = PackedWeights<W, 8>;
using Packed256S16 = PackedWeights256<std::int16_t>;  // G = 2
using Packed256S8 = PackedWeights256<std::int8_t>;    // G = 4
// `w` holds int8 values (as int16, like every other path).
Packed256S16 pack_weights_s16_avx2(const std::int16_t* w, int cols, int depth);
Packed256S8 pack_weights_s8_avx2(const std::int16_t* w, int cols, int depth);

// c[m * w.cols + j] = sum_k a(m, k) * w[j][k]. Throws std::invalid_argument when the view's
// segments do not tile w.depth in whole groups. The uint8 form requires every activation
// <= 127 (see above; not checked: the caller's ReLU and clamp guarantee it).
void gemm_avx2_packed(const RowsView<std::int16_t>& a, const Packed256S16& w, std::int32_t* c);
void gemm_avx2_packed(const RowsView<std::uint8_t>& a, const Packed256S8& w, std::int32_t* c);

// Requantisation, bit-identical to the scalar code in network.cpp (same float operations,
// nearbyint in the current rounding mode):
//   out[g * cols + j] = clamp(nearbyint(float(max_p acc[(g * pool + p) * cols + j] + bias[j])
//                                       * to_real[j] * inv), relu ? 0 : -127, 127)
void requantize_avx2(const std::int32_t* acc, int groups, int pool, int cols,
                     const std::int32_t* bias, const float* to_real, float inv, bool relu,
                     std::int16_t* out);
// The same with ReLU, written as bytes (0..127) for the uint8 kernel.
void requantize_relu_avx2(const std::int32_t* acc, int groups, int pool, int cols,
                          const std::int32_t* bias, const float* to_real, float inv,
                          std::uint8_t* out);
// out[i] = clamp(nearbyint(in[i] * inv), -127, 127): the network's input quantisation.
void quantize_input_avx2(const float* in, int n, float inv, std::int16_t* out);

}  // namespace marvin::perception::kws::detail
