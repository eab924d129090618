// The AVX-512 VNNI int8 kernel (see gemm_avx512.h). Compiled for AVX-512 with function
// attributes and chosen at run time, so the library still builds and runs on CPUs without it
// (and on ARM, where the kernels compile to "unavailable" stubs).
//
// Blocking: 6 rows x 4 blocks of 16 output channels = 24 accumulators in registers, 4 weight
// loads per 24 multiply-adds. The two convolutions (99% of the work) run on bytes; the small
// dense layers, whose inputs may be negative, on int16.
#include "perception/kws/gemm_avx512.h"

#include <algorithm>
#include <cstddef>
#include <cstring>
#include <stdexcept>
#include <string>

#include "perception/kws/network.h"

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
// GCC 12 reports false "may be used uninitialized" errors inside its own AVX-512 intrinsics
// (the _mm512_undefined_* placeholders they pass); nothing of ours is concerned.
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <immintrin.h>
#define MARVIN_KWS_HAVE_AVX512_KERNEL 1
#define MARVIN_KWS_AVX512 __attribute__((target("avx512f,avx512bw,avx512vl,avx512vnni")))
#endif

namespace marvin::perception::kws {

namespace detail {

PackedS16 pack_weights_s16(const std::int16_t* w, int cols, int depth) {
  return pack_weights<std::int16_t, 16>(w, cols, depth, 2);
}

PackedS8 pack_weights_s8(const std::int16_t* w, int cols, int depth) {
  return pack_weights<std::int8_t, 16>(w, cols, depth, 4);
}

}  // namespace detail

#ifdef MARVIN_KWS_HAVE_AVX512_KERNEL

namespace {

using detail::PackedWeights512;
using detail::RowsView;

// The first `bytes` bytes at p as the low bytes of a 32-bit lane (the rest zero).
inline std::int32_t load_group(const void* p, std::size_t bytes = 4) {
  std::int32_t v = 0;
  std::memcpy(&v, p, bytes);
  return v;
}

// acc += pairwise products of x and w. Inline assembly rather than _mm512_dpwssd_epi32: GCC 12
// copies every accumulator twice around each intrinsic call (it does not see that the
// instruction updates its destination in place), which made the kernel twice as slow.
MARVIN_KWS_AVX512 inline __m512i dpwssd(__m512i acc, __m512i x, __m512i w) {
  asm("vpdpwssd %[w], %[x], %[acc]" : [acc] "+v"(acc) : [x] "v"(x), [w] "v"(w));
  return acc;
}

// acc += sums of 4 products of unsigned bytes of x and signed bytes of w (same reason).
MARVIN_KWS_AVX512 inline __m512i dpbusd(__m512i acc, __m512i x, __m512i w) {
  asm("vpdpbusd %[w], %[x], %[acc]" : [acc] "+v"(acc) : [x] "v"(x), [w] "v"(w));
  return acc;
}

// What differs between the two element types.
struct S16 {
  using A = std::int16_t;
  using W = std::int16_t;
  static constexpr int kGroup = 2;
  MARVIN_KWS_AVX512 static __m512i mac(__m512i acc, __m512i x, __m512i w) {
    return dpwssd(acc, x, w);
  }
};
struct U8 {
  using A = std::uint8_t;
  using W = std::int8_t;
  static constexpr int kGroup = 4;
  MARVIN_KWS_AVX512 static __m512i mac(__m512i acc, __m512i x, __m512i w) {
    return dpbusd(acc, x, w);
  }
};

inline __mmask16 lane_mask(int n) {
  return n >= 16 ? static_cast<__mmask16>(0xFFFF) : static_cast<__mmask16>((1u << n) - 1u);
}

// R rows from m0 x NB blocks of 16 output channels from block b0.
template <typename T, int R, int NB>
MARVIN_KWS_AVX512 void block(const RowsView<typename T::A>& a, int m0,
                             const PackedWeights512<typename T::W>& w, int b0, std::int32_t* c) {
  using A = typename T::A;
  constexpr int G = T::kGroup;
  __m512i acc[R][NB];
#pragma GCC unroll 8
  for (int r = 0; r < R; ++r) {
#pragma GCC unroll 8
    for (int j = 0; j < NB; ++j) acc[r][j] = _mm512_setzero_si512();
  }
  const A* rows[R];
#pragma GCC unroll 8
  for (int r = 0; r < R; ++r) rows[r] = a.base + a.row_offsets[m0 + r];
  const std::ptrdiff_t w_step = static_cast<std::ptrdiff_t>(w.blocks) * 16 * G;
  const typename T::W* wp = w.data.data() + static_cast<std::ptrdiff_t>(b0) * 16 * G;
  const int segments = w.depth / a.seg_len;
  const int seg_groups = a.seg_len / G;
  for (int s = 0; s < segments; ++s) {
    const std::ptrdiff_t so = static_cast<std::ptrdiff_t>(s) * a.seg_stride;
    for (int p = 0; p < seg_groups; ++p) {
      __m512i wv[NB];
#pragma GCC unroll 8
      for (int j = 0; j < NB; ++j) wv[j] = _mm512_loadu_si512(wp + j * 16 * G);
#pragma GCC unroll 8
      for (int r = 0; r < R; ++r) {
        const __m512i x = _mm512_set1_epi32(load_group(rows[r] + so + G * p));
#pragma GCC unroll 8
        for (int j = 0; j < NB; ++j) acc[r][j] = T::mac(acc[r][j], x, wv[j]);
      }
      wp += w_step;
    }
  }
  // One segment that is not whole groups: the last elements, the rest of the group zero (and
  // not read: it may lie past the end of the matrix).
  if (const int rest = a.seg_len % G; rest != 0) {
    __m512i wv[NB];
#pragma GCC unroll 8
    for (int j = 0; j < NB; ++j) wv[j] = _mm512_loadu_si512(wp + j * 16 * G);
#pragma GCC unroll 8
    for (int r = 0; r < R; ++r) {
      const __m512i x = _mm512_set1_epi32(load_group(rows[r] + seg_groups * G,
                                                     static_cast<std::size_t>(rest) * sizeof(A)));
#pragma GCC unroll 8
      for (int j = 0; j < NB; ++j) acc[r][j] = T::mac(acc[r][j], x, wv[j]);
    }
  }
#pragma GCC unroll 8
  for (int r = 0; r < R; ++r) {
    std::int32_t* out = c + static_cast<std::ptrdiff_t>(m0 + r) * w.cols;
#pragma GCC unroll 8
    for (int j = 0; j < NB; ++j) {
      const int col = (b0 + j) * 16;
      _mm512_mask_storeu_epi32(out + col, lane_mask(w.cols - col), acc[r][j]);
    }
  }
}

constexpr int kRowBlock = 6;

template <typename T, int NB>
void blocks_of(const RowsView<typename T::A>& a, const PackedWeights512<typename T::W>& w, int b0,
               std::int32_t* c) {
  int m = 0;
  for (; m + kRowBlock <= a.rows; m += kRowBlock) block<T, kRowBlock, NB>(a, m, w, b0, c);
  switch (a.rows - m) {
    case 5: block<T, 5, NB>(a, m, w, b0, c); break;
    case 4: block<T, 4, NB>(a, m, w, b0, c); break;
    case 3: block<T, 3, NB>(a, m, w, b0, c); break;
    case 2: block<T, 2, NB>(a, m, w, b0, c); break;
    case 1: block<T, 1, NB>(a, m, w, b0, c); break;
    default: break;
  }
}

template <typename T>
void gemm(const RowsView<typename T::A>& a, const PackedWeights512<typename T::W>& w,
          std::int32_t* c) {
  const bool one_segment = a.seg_len == w.depth;
  if (a.seg_len <= 0 || w.depth % a.seg_len != 0 || (!one_segment && a.seg_len % T::kGroup != 0)) {
    throw std::invalid_argument("kws AVX-512 kernel: segments of " + std::to_string(a.seg_len) +
                                " must be whole groups of " + std::to_string(T::kGroup) +
                                " and tile the depth " + std::to_string(w.depth));
  }
  for (int b0 = 0; b0 < w.blocks; b0 += 4) {
    switch (std::min(4, w.blocks - b0)) {
      case 4: blocks_of<T, 4>(a, w, b0, c); break;
      case 3: blocks_of<T, 3>(a, w, b0, c); break;
      case 2: blocks_of<T, 2>(a, w, b0, c); break;
      default: blocks_of<T, 1>(a, w, b0, c); break;
    }
  }
}

template <typename Out>
MARVIN_KWS_AVX512 void requantize(const std::int32_t* acc, int groups, int pool, int cols,
                                  const std::int32_t* bias, const float* to_real, float inv,
                                  bool relu, Out* out) {
  const __m512 vinv = _mm512_set1_ps(inv);
  const __m512 lo = _mm512_set1_ps(relu ? 0.0f : -127.0f);
  const __m512 hi = _mm512_set1_ps(127.0f);
  for (int g = 0; g < groups; ++g) {
    for (int c0 = 0; c0 < cols; c0 += 16) {
      const __mmask16 k = lane_mask(cols - c0);
      const std::int32_t* r = acc + static_cast<std::ptrdiff_t>(g) * pool * cols + c0;
      __m512i m = _mm512_maskz_loadu_epi32(k, r);
      for (int p = 1; p < pool; ++p) {
        m = _mm512_max_epi32(
            m, _mm512_maskz_loadu_epi32(k, r + static_cast<std::ptrdiff_t>(p) * cols));
      }
      m = _mm512_add_epi32(m, _mm512_maskz_loadu_epi32(k, bias + c0));
      __m512 f = _mm512_mul_ps(_mm512_cvtepi32_ps(m), _mm512_maskz_loadu_ps(k, to_real + c0));
      f = _mm512_mul_ps(f, vinv);
      f = _mm512_roundscale_ps(f, _MM_FROUND_CUR_DIRECTION | _MM_FROUND_NO_EXC);
      f = _mm512_min_ps(_mm512_max_ps(f, lo), hi);
      const __m512i q = _mm512_cvtps_epi32(f);
      Out* o = out + static_cast<std::ptrdiff_t>(g) * cols + c0;
      if constexpr (sizeof(Out) == 2) {
        _mm256_mask_storeu_epi16(o, k, _mm512_cvtepi32_epi16(q));
      } else {
        _mm_mask_storeu_epi8(o, k, _mm512_cvtepi32_epi8(q));
      }
    }
  }
}

}  // namespace

bool gemm_s16_avx512_available() {
  static const bool available = __builtin_cpu_supports("avx512f") &&
                                __builtin_cpu_supports("avx512bw") &&
                                __builtin_cpu_supports("avx512vl") &&
                                __builtin_cpu_supports("avx512vnni");
  return available;
}

namespace detail {

void gemm_avx512_packed(const RowsView<std::int16_t>& a, const PackedS16& w, std::int32_t* c) {
  gemm<S16>(a, w, c);
}

void gemm_avx512_packed(const RowsView<std::uint8_t>& a, const PackedS8& w, std::int32_t* c) {
  gemm<U8>(a, w, c);
}

void requantize_avx512(const std::int32_t* acc, int groups, int pool, int cols,
                       const std::int32_t* bias, const float* to_real, float inv, bool relu,
                       std::int16_t* out) {
  requantize(acc, groups, pool, cols, bias, to_real, inv, relu, out);
}

void requantize_relu_avx512(const std::int32_t* acc, int groups, int pool, int cols,
                            const std::int32_t* bias, const float* to_real, float inv,
                            std::uint8_t* out) {
  requantize(acc, groups, pool, cols, bias, to_real, inv, true, out);
}

MARVIN_KWS_AVX512 void quantize_input_u8_avx512(const float* in, int n, float inv,
                                                std::uint8_t* out) {
  const __m512 vinv = _mm512_set1_ps(inv);
  const __m512 lo = _mm512_set1_ps(-127.0f);
  const __m512 hi = _mm512_set1_ps(127.0f);
  const __m512i shift = _mm512_set1_epi32(128);
  for (int i = 0; i < n; i += 16) {
    const __mmask16 k = lane_mask(n - i);
    __m512 f = _mm512_mul_ps(_mm512_maskz_loadu_ps(k, in + i), vinv);
    f = _mm512_roundscale_ps(f, _MM_FROUND_CUR_DIRECTION | _MM_FROUND_NO_EXC);
    f = _mm512_min_ps(_mm512_max_ps(f, lo), hi);
    const __m512i q = _mm512_add_epi32(_mm512_cvtps_epi32(f), shift);
    _mm_mask_storeu_epi8(out + i, k, _mm512_cvtepi32_epi8(q));
  }
}

}  // namespace detail

namespace {

std::vector<std::int32_t> plain_rows(int rows, int depth) {
  std::vector<std::int32_t> offsets(static_cast<std::size_t>(rows));
  for (int m = 0; m < rows; ++m) offsets[static_cast<std::size_t>(m)] = m * depth;
  return offsets;
}

}  // namespace

void gemm_s16_avx512(const std::int16_t* a, int rows, const std::int16_t* w, int cols, int depth,
                     std::int32_t* c) {
  if (rows <= 0 || cols <= 0 || depth <= 0) return;
  const std::vector<std::int32_t> offsets = plain_rows(rows, depth);
  detail::gemm_avx512_packed(detail::RowsView<std::int16_t>{a, offsets.data(), rows, depth, depth},
                             detail::pack_weights_s16(w, cols, depth), c);
}

void gemm_u8s8_avx512(const std::uint8_t* a, int rows, const std::int16_t* w, int cols,
                      int depth, std::int32_t* c) {
  if (rows <= 0 || cols <= 0 || depth <= 0) return;
  const std::vector<std::int32_t> offsets = plain_rows(rows, depth);
  detail::gemm_avx512_packed(detail::RowsView<std::uint8_t>{a, offsets.data(), rows, depth, depth},
                             detail::pack_weights_s8(w, cols, depth), c);
}

#else

bool gemm_s16_avx512_available() { return false; }

namespace {

[[noreturn]] void not_compiled() {
  throw std::logic_error("kws: the AVX-512 kernel is not compiled in");
}

}  // namespace

void gemm_s16_avx512(const std::int16_t*, int, const std::int16_t*, int, int, std::int32_t*) {
  not_compiled();
}
void gemm_u8s8_avx512(const std::uint8_t*, int, const std::int16_t*, int, int, std::int32_t*) {
  not_compiled();
}

namespace detail {

void gemm_avx512_packed(const RowsView<std::int16_t>&, const PackedS16&, std::int32_t*) {
  not_compiled();
}
void gemm_avx512_packed(const RowsView<std::uint8_t>&, const PackedS8&, std::int32_t*) {
  not_compiled();
}
void requantize_avx512(const std::int32_t*, int, int, int, const std::int32_t*, const float*,
                       float, bool, std::int16_t*) {
  not_compiled();
}
void requantize_relu_avx512(const std::int32_t*, int, int, int, const std::int32_t*,
                            const float*, float, std::uint8_t*) {
  not_compiled();
}
void quantize_input_u8_avx512(const float*, int, float, std::uint8_t*) { not_compiled(); }

}  // namespace detail

#endif

}  // namespace marvin::perception::kws
