// The AVX2 int8 kernel (see gemm_avx2.h). Compiled for AVX2 with function attributes and
// chosen at run time, so the library still builds and runs on CPUs without it (and on ARM,
// where the kernels compile to "unavailable" stubs).
//
// Blocking: kRows rows x kBlocks = 2 blocks of 8 output channels in registers. AVX2 has 16
// vector registers: the accumulators, one weight vector per block, the broadcast activations,
// a temporary and (bytes) the vector of ones. int16: 6 rows (12 + 2 + 1 + 1 = 16); bytes:
// 4 rows (8 + 2 + 1 + 1 + 1; 6 rows spilt an accumulator and was no faster). Per group of
// inputs, 2 weight loads and kRows broadcasts feed 2 x kRows multiply-adds. Measured on this
// machine (kws_bench, AVX2 path forced): 4x2 blocks for both 118 us, 6x2 109 us, 3x3 124 us,
// 2x4 137 us per window: the differences are near the noise of a shared machine; the bound
// is the two multiply ports (about 600 K vpmaddwd/vpmaddubsw per window).
#include "perception/kws/gemm_avx2.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <stdexcept>
#include <string>

#include "perception/kws/network.h"

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
#define MARVIN_KWS_HAVE_AVX2_KERNEL 1
#define MARVIN_KWS_AVX2 __attribute__((target("avx2")))
#endif

namespace marvin::perception::kws {

namespace detail {

Packed256S16 pack_weights_s16_avx2(const std::int16_t* w, int cols, int depth) {
  return pack_weights<std::int16_t, 8>(w, cols, depth, 2);
}

Packed256S8 pack_weights_s8_avx2(const std::int16_t* w, int cols, int depth) {
  return pack_weights<std::int8_t, 8>(w, cols, depth, 4);
}

}  // namespace detail

#ifdef MARVIN_KWS_HAVE_AVX2_KERNEL

namespace {

using detail::PackedWeights256;
using detail::RowsView;

// The first `bytes` bytes at p as the low bytes of a 32-bit lane (the rest zero).
inline std::int32_t load_group2(const void* p, std::size_t bytes = 4) {
  std::int32_t v = 0;
  std::memcpy(&v, p, bytes);
  return v;
}

// What differs between the two element types.
struct S16x2 {
  using A = std::int16_t;
  using W = std::int16_t;
  static constexpr int kGroup = 2;
  static constexpr int kRows = 6;  // rows per register block (see the top of the file)
  MARVIN_KWS_AVX2 static __m256i mac(__m256i acc, __m256i x, __m256i w) {
    return _mm256_add_epi32(acc, _mm256_madd_epi16(x, w));
  }
};
struct U8x4 {
  using A = std::uint8_t;
  using W = std::int8_t;
  static constexpr int kGroup = 4;
  static constexpr int kRows = 4;
  // Exact for x <= 127 (gemm_avx2.h): the int16 pair sums of vpmaddubsw never saturate.
  MARVIN_KWS_AVX2 static __m256i mac(__m256i acc, __m256i x, __m256i w) {
    const __m256i pairs = _mm256_maddubs_epi16(x, w);
    return _mm256_add_epi32(acc, _mm256_madd_epi16(pairs, _mm256_set1_epi16(1)));
  }
};

// Lanes 0..n-1 of a maskstore mask.
MARVIN_KWS_AVX2 inline __m256i lane_mask8(int n) {
  return _mm256_cmpgt_epi32(_mm256_set1_epi32(n), _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7));
}

// R rows from m0 x NB blocks of 8 output channels from block b0.
template <typename T, int R, int NB>
MARVIN_KWS_AVX2 void block256(const RowsView<typename T::A>& a, int m0,
                              const PackedWeights256<typename T::W>& w, int b0, std::int32_t* c) {
  using A = typename T::A;
  constexpr int G = T::kGroup;
  __m256i acc[R][NB];
#pragma GCC unroll 8
  for (int r = 0; r < R; ++r) {
#pragma GCC unroll 8
    for (int j = 0; j < NB; ++j) acc[r][j] = _mm256_setzero_si256();
  }
  const A* rows[R];
#pragma GCC unroll 8
  for (int r = 0; r < R; ++r) rows[r] = a.base + a.row_offsets[m0 + r];
  const std::ptrdiff_t w_step = static_cast<std::ptrdiff_t>(w.blocks) * 8 * G;
  const typename T::W* wp = w.data.data() + static_cast<std::ptrdiff_t>(b0) * 8 * G;
  const int segments = w.depth / a.seg_len;
  const int seg_groups = a.seg_len / G;
  for (int s = 0; s < segments; ++s) {
    const std::ptrdiff_t so = static_cast<std::ptrdiff_t>(s) * a.seg_stride;
    for (int p = 0; p < seg_groups; ++p) {
      __m256i wv[NB];
#pragma GCC unroll 8
      for (int j = 0; j < NB; ++j) {
        wv[j] = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(wp + j * 8 * G));
      }
#pragma GCC unroll 8
      for (int r = 0; r < R; ++r) {
        const __m256i x = _mm256_set1_epi32(load_group2(rows[r] + so + G * p));
#pragma GCC unroll 8
        for (int j = 0; j < NB; ++j) acc[r][j] = T::mac(acc[r][j], x, wv[j]);
      }
      wp += w_step;
    }
  }
  // One segment that is not whole groups: the last elements, the rest of the group zero (and
  // not read: it may lie past the end of the matrix).
  if (const int rest = a.seg_len % G; rest != 0) {
    __m256i wv[NB];
#pragma GCC unroll 8
    for (int j = 0; j < NB; ++j) {
      wv[j] = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(wp + j * 8 * G));
    }
#pragma GCC unroll 8
    for (int r = 0; r < R; ++r) {
      const __m256i x = _mm256_set1_epi32(
          load_group2(rows[r] + seg_groups * G, static_cast<std::size_t>(rest) * sizeof(A)));
#pragma GCC unroll 8
      for (int j = 0; j < NB; ++j) acc[r][j] = T::mac(acc[r][j], x, wv[j]);
    }
  }
#pragma GCC unroll 8
  for (int r = 0; r < R; ++r) {
    std::int32_t* out = c + static_cast<std::ptrdiff_t>(m0 + r) * w.cols;
#pragma GCC unroll 8
    for (int j = 0; j < NB; ++j) {
      const int col = (b0 + j) * 8;
      if (w.cols - col >= 8) {
        _mm256_storeu_si256(reinterpret_cast<__m256i*>(out + col), acc[r][j]);
      } else {
        _mm256_maskstore_epi32(out + col, lane_mask8(w.cols - col), acc[r][j]);
      }
    }
  }
}

constexpr int kBlocks = 2;

template <typename T, int NB>
void blocks_of256(const RowsView<typename T::A>& a, const PackedWeights256<typename T::W>& w,
                  int b0, std::int32_t* c) {
  int m = 0;
  for (; m + T::kRows <= a.rows; m += T::kRows) block256<T, T::kRows, NB>(a, m, w, b0, c);
  switch (a.rows - m) {
    case 5:
      block256<T, 5, NB>(a, m, w, b0, c);
      break;
    case 4:
      block256<T, 4, NB>(a, m, w, b0, c);
      break;
    case 3:
      block256<T, 3, NB>(a, m, w, b0, c);
      break;
    case 2:
      block256<T, 2, NB>(a, m, w, b0, c);
      break;
    case 1:
      block256<T, 1, NB>(a, m, w, b0, c);
      break;
    default:
      break;
  }
}

template <typename T>
void gemm256(const RowsView<typename T::A>& a, const PackedWeights256<typename T::W>& w,
             std::int32_t* c) {
  const bool one_segment = a.seg_len == w.depth;
  if (a.seg_len <= 0 || w.depth % a.seg_len != 0 || (!one_segment && a.seg_len % T::kGroup != 0)) {
    throw std::invalid_argument("kws AVX2 kernel: segments of " + std::to_string(a.seg_len) +
                                " must be whole groups of " + std::to_string(T::kGroup) +
                                " and tile the depth " + std::to_string(w.depth));
  }
  if (a.rows == 1) {
    // A dense layer: one row, so the weights are the only thing to reuse: as many blocks at
    // once as registers allow.
    for (int b0 = 0; b0 < w.blocks; b0 += 4) {
      switch (std::min(4, w.blocks - b0)) {
        case 4:
          block256<T, 1, 4>(a, 0, w, b0, c);
          break;
        case 3:
          block256<T, 1, 3>(a, 0, w, b0, c);
          break;
        case 2:
          block256<T, 1, 2>(a, 0, w, b0, c);
          break;
        default:
          block256<T, 1, 1>(a, 0, w, b0, c);
          break;
      }
    }
    return;
  }
  int b0 = 0;
  for (; b0 + kBlocks <= w.blocks; b0 += kBlocks) blocks_of256<T, kBlocks>(a, w, b0, c);
  for (; b0 < w.blocks; ++b0) blocks_of256<T, 1>(a, w, b0, c);
}

// The scalar requantisation of network.cpp, for the columns past the last whole vector.
inline std::int32_t requantize_one(std::int32_t m, std::int32_t bias, float to_real, float inv,
                                   bool relu) {
  float q = std::nearbyint(static_cast<float>(m + bias) * to_real * inv);
  q = std::clamp(q, relu ? 0.0f : -127.0f, 127.0f);
  return static_cast<std::int32_t>(q);
}

template <typename Out>
MARVIN_KWS_AVX2 void requantize256(const std::int32_t* acc, int groups, int pool, int cols,
                                   const std::int32_t* bias, const float* to_real, float inv,
                                   bool relu, Out* out) {
  const __m256 vinv = _mm256_set1_ps(inv);
  const __m256 lo = _mm256_set1_ps(relu ? 0.0f : -127.0f);
  const __m256 hi = _mm256_set1_ps(127.0f);
  const int cols_vec = cols / 8 * 8;
  for (int g = 0; g < groups; ++g) {
    const std::int32_t* r = acc + static_cast<std::ptrdiff_t>(g) * pool * cols;
    Out* o = out + static_cast<std::ptrdiff_t>(g) * cols;
    for (int c0 = 0; c0 < cols_vec; c0 += 8) {
      __m256i m = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(r + c0));
      for (int p = 1; p < pool; ++p) {
        m = _mm256_max_epi32(m, _mm256_loadu_si256(reinterpret_cast<const __m256i*>(
                                    r + static_cast<std::ptrdiff_t>(p) * cols + c0)));
      }
      m = _mm256_add_epi32(m, _mm256_loadu_si256(reinterpret_cast<const __m256i*>(bias + c0)));
      __m256 f = _mm256_mul_ps(_mm256_cvtepi32_ps(m), _mm256_loadu_ps(to_real + c0));
      f = _mm256_mul_ps(f, vinv);
      f = _mm256_round_ps(f, _MM_FROUND_CUR_DIRECTION);
      f = _mm256_min_ps(_mm256_max_ps(f, lo), hi);
      const __m256i q = _mm256_cvtps_epi32(f);
      const __m128i q16 =
          _mm_packs_epi32(_mm256_castsi256_si128(q), _mm256_extracti128_si256(q, 1));
      if constexpr (sizeof(Out) == 2) {
        _mm_storeu_si128(reinterpret_cast<__m128i*>(o + c0), q16);
      } else {
        _mm_storel_epi64(reinterpret_cast<__m128i*>(o + c0), _mm_packus_epi16(q16, q16));
      }
    }
    for (int j = cols_vec; j < cols; ++j) {
      std::int32_t m = r[j];
      for (int p = 1; p < pool; ++p) m = std::max(m, r[static_cast<std::ptrdiff_t>(p) * cols + j]);
      o[j] = static_cast<Out>(requantize_one(m, bias[j], to_real[j], inv, relu));
    }
  }
}

}  // namespace

bool gemm_s16_avx2_available() {
  static const bool available = __builtin_cpu_supports("avx2");
  return available;
}

namespace detail {

void gemm_avx2_packed(const RowsView<std::int16_t>& a, const Packed256S16& w, std::int32_t* c) {
  gemm256<S16x2>(a, w, c);
}

void gemm_avx2_packed(const RowsView<std::uint8_t>& a, const Packed256S8& w, std::int32_t* c) {
  gemm256<U8x4>(a, w, c);
}

void requantize_avx2(const std::int32_t* acc, int groups, int pool, int cols,
                     const std::int32_t* bias, const float* to_real, float inv, bool relu,
                     std::int16_t* out) {
  requantize256(acc, groups, pool, cols, bias, to_real, inv, relu, out);
}

void requantize_relu_avx2(const std::int32_t* acc, int groups, int pool, int cols,
                          const std::int32_t* bias, const float* to_real, float inv,
                          std::uint8_t* out) {
  requantize256(acc, groups, pool, cols, bias, to_real, inv, true, out);
}

MARVIN_KWS_AVX2 void quantize_input_avx2(const float* in, int n, float inv, std::int16_t* out) {
  const __m256 vinv = _mm256_set1_ps(inv);
  const __m256 lo = _mm256_set1_ps(-127.0f);
  const __m256 hi = _mm256_set1_ps(127.0f);
  const int n_vec = n / 8 * 8;
  for (int i = 0; i < n_vec; i += 8) {
    __m256 f = _mm256_mul_ps(_mm256_loadu_ps(in + i), vinv);
    f = _mm256_round_ps(f, _MM_FROUND_CUR_DIRECTION);
    f = _mm256_min_ps(_mm256_max_ps(f, lo), hi);
    const __m256i q = _mm256_cvtps_epi32(f);
    _mm_storeu_si128(reinterpret_cast<__m128i*>(out + i),
                     _mm_packs_epi32(_mm256_castsi256_si128(q), _mm256_extracti128_si256(q, 1)));
  }
  for (int i = n_vec; i < n; ++i) {
    out[i] = static_cast<std::int16_t>(std::clamp(std::nearbyint(in[i] * inv), -127.0f, 127.0f));
  }
}

}  // namespace detail

namespace {

std::vector<std::int32_t> plain_rows256(int rows, int depth) {
  std::vector<std::int32_t> offsets(static_cast<std::size_t>(rows));
  for (int m = 0; m < rows; ++m) offsets[static_cast<std::size_t>(m)] = m * depth;
  return offsets;
}

}  // namespace

void gemm_s16_avx2(const std::int16_t* a, int rows, const std::int16_t* w, int cols, int depth,
                   std::int32_t* c) {
  if (rows <= 0 || cols <= 0 || depth <= 0) return;
  const std::vector<std::int32_t> offsets = plain_rows256(rows, depth);
  detail::gemm_avx2_packed(detail::RowsView<std::int16_t>{a, offsets.data(), rows, depth, depth},
                           detail::pack_weights_s16_avx2(w, cols, depth), c);
}

void gemm_u8s8_avx2(const std::uint8_t* a, int rows, const std::int16_t* w, int cols, int depth,
                    std::int32_t* c) {
  if (rows <= 0 || cols <= 0 || depth <= 0) return;
  const std::vector<std::int32_t> offsets = plain_rows256(rows, depth);
  detail::gemm_avx2_packed(detail::RowsView<std::uint8_t>{a, offsets.data(), rows, depth, depth},
                           detail::pack_weights_s8_avx2(w, cols, depth), c);
}

#else

bool gemm_s16_avx2_available() { return false; }

namespace {

[[noreturn]] void avx2_not_compiled() {
  throw std::logic_error("kws: the AVX2 kernel is not compiled in");
}

}  // namespace

void gemm_s16_avx2(const std::int16_t*, int, const std::int16_t*, int, int, std::int32_t*) {
  avx2_not_compiled();
}
void gemm_u8s8_avx2(const std::uint8_t*, int, const std::int16_t*, int, int, std::int32_t*) {
  avx2_not_compiled();
}

namespace detail {

void gemm_avx2_packed(const RowsView<std::int16_t>&, const Packed256S16&, std::int32_t*) {
  avx2_not_compiled();
}
void gemm_avx2_packed(const RowsView<std::uint8_t>&, const Packed256S8&, std::int32_t*) {
  avx2_not_compiled();
}
void requantize_avx2(const std::int32_t*, int, int, int, const std::int32_t*, const float*, float,
                     bool, std::int16_t*) {
  avx2_not_compiled();
}
void requantize_relu_avx2(const std::int32_t*, int, int, int, const std::int32_t*, const float*,
                          float, std::uint8_t*) {
  avx2_not_compiled();
}
void quantize_input_avx2(const float*, int, float, std::int16_t*) { avx2_not_compiled(); }

}  // namespace detail

#endif

}  // namespace marvin::perception::kws
