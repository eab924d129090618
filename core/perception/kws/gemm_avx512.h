// Internal: the AVX-512 VNNI int8 path of Int8Inference (gemm_avx512.cpp). Weights are packed
// once, when the network is loaded, so that one 64-byte load holds 16 output channels x one
// group of inputs; one VNNI instruction multiplies that by a broadcast group of activations
// and adds into 16 int32 accumulators, so the sums land in output-channel lanes with no
// horizontal reduction. The activation matrix is read in place through a RowsView (im2col
// fused into the kernel), so the convolutions copy nothing.
//
// Two element types, both exact in int32:
//   int16 x int16, groups of 2 (vpdpwssd): any signed activations (the network's input).
//   uint8 x int8, groups of 4 (vpdpbusd, twice the work per instruction): activations that
//   are never negative, i.e. after a ReLU (conv2's, in 0..127), or signed ones shifted by
//   +128 with the shift's contribution subtracted afterwards (conv1's input).
// Call only when gemm_s16_avx512_available().
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace marvin::perception::kws::detail {

// Weights [cols][depth] rearranged to [depth/G groups][cols/L blocks][L cols][G], zero padded
// to whole groups and blocks (the padding contributes nothing to the sums): one vector load
// holds L output channels x one group of G inputs. L is 16 for 512-bit vectors, 8 for 256-bit
// (gemm_avx2.h); G is 2 for int16 weights, 4 for int8.
template <typename W, int L>
struct PackedWeights {
  int cols = 0;
  int depth = 0;
  int groups = 0;
  int blocks = 0;
  std::vector<W> data;
};
// `w` [cols][depth] holds int8 values (as int16, like every other path).
template <typename W, int L>
PackedWeights<W, L> pack_weights(const std::int16_t* w, int cols, int depth, int group) {
  PackedWeights<W, L> p;
  p.cols = cols;
  p.depth = depth;
  p.groups = (depth + group - 1) / group;
  p.blocks = (cols + L - 1) / L;
  const auto g = static_cast<std::size_t>(group);
  const auto blocks = static_cast<std::size_t>(p.blocks);
  p.data.assign(static_cast<std::size_t>(p.groups) * blocks * L * g, 0);
  for (int j = 0; j < cols; ++j) {
    for (int k = 0; k < depth; ++k) {
      const std::size_t at = ((static_cast<std::size_t>(k / group) * blocks +
                               static_cast<std::size_t>(j / L)) * L +
                              static_cast<std::size_t>(j % L)) * g +
                             static_cast<std::size_t>(k % group);
      p.data[at] = static_cast<W>(w[static_cast<std::ptrdiff_t>(j) * depth + k]);
    }
  }
  return p;
}
template <typename W>
using PackedWeights512 = PackedWeights<W, 16>;
using PackedS16 = PackedWeights512<std::int16_t>;  // G = 2
using PackedS8 = PackedWeights512<std::int8_t>;    // G = 4
// `w` holds int8 values (as int16, like every other path).
PackedS16 pack_weights_s16(const std::int16_t* w, int cols, int depth);
PackedS8 pack_weights_s8(const std::int16_t* w, int cols, int depth);

// The activation matrix without copying it: element k of row m is
//   base[row_offsets[m] + (k / seg_len) * seg_stride + k % seg_len].
// A convolution's rows are its output positions and each segment one kernel row (conv1:
// 8 frequencies of one frame; conv2: 4 frequencies x 64 maps of one frame). seg_len must be
// a whole number of groups unless it is the whole depth (a plain matrix: seg_len = depth).
template <typename A>
struct RowsView {
  const A* base = nullptr;
  const std::int32_t* row_offsets = nullptr;
  int rows = 0;
  int seg_len = 0;
  int seg_stride = 0;
};

// c[m * w.cols + j] = sum_k a(m, k) * w[j][k]. Throws std::invalid_argument when the view's
// segments do not tile w.depth in whole groups.
void gemm_avx512_packed(const RowsView<std::int16_t>& a, const PackedS16& w, std::int32_t* c);
void gemm_avx512_packed(const RowsView<std::uint8_t>& a, const PackedS8& w, std::int32_t* c);

// Requantisation, bit-identical to the scalar code in network.cpp (same float operations,
// nearbyint in the current rounding mode):
//   out[g * cols + j] = clamp(nearbyint(float(max_p acc[(g * pool + p) * cols + j] + bias[j])
//                                       * to_real[j] * inv), relu ? 0 : -127, 127)
void requantize_avx512(const std::int32_t* acc, int groups, int pool, int cols,
                       const std::int32_t* bias, const float* to_real, float inv, bool relu,
                       std::int16_t* out);
// The same with ReLU, written as bytes for the uint8 kernel.
void requantize_relu_avx512(const std::int32_t* acc, int groups, int pool, int cols,
                            const std::int32_t* bias, const float* to_real, float inv,
                            std::uint8_t* out);
// out[i] = clamp(nearbyint(in[i] * inv), -127, 127) + 128: the network's input quantisation,
// shifted to 1..255 so the byte kernel can take it; the caller subtracts 128 * sum_k w[j][k]
// from every sum (exact: it is all integer arithmetic).
void quantize_input_u8_avx512(const float* in, int n, float inv, std::uint8_t* out);

}  // namespace marvin::perception::kws::detail
