// The AVX2 int8 kernel: int8 values held as int16, multiplied pairwise and summed into int32
// lanes by vpmaddwd (16 multiply-accumulates per instruction), in blocks of 2 rows x 4 output
// channels so each loaded vector is used several times. Compiled for AVX2 with a function
// attribute and chosen at run time, so the library still runs on CPUs without it (and on
// ARM, where this file compiles to the "unavailable" stubs). Sizes that are not whole blocks
// (never the network's) are finished in scalar code, so the kernel takes any matrix.
#include <cstddef>
#include <cstdint>
#include <stdexcept>

#include "perception/kws/network.h"

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
#define MARVIN_KWS_HAVE_AVX2_KERNEL 1
#endif

namespace marvin::perception::kws {

#ifdef MARVIN_KWS_HAVE_AVX2_KERNEL

namespace {

__attribute__((target("avx2"))) inline __m128i sum4(__m256i c0, __m256i c1, __m256i c2,
                                                     __m256i c3) {
  const __m256i s01 = _mm256_hadd_epi32(c0, c1);
  const __m256i s23 = _mm256_hadd_epi32(c2, c3);
  const __m256i s = _mm256_hadd_epi32(s01, s23);
  return _mm_add_epi32(_mm256_castsi256_si128(s), _mm256_extracti128_si256(s, 1));
}

__attribute__((target("avx2"))) inline __m256i load(const std::int16_t* p) {
  return _mm256_loadu_si256(reinterpret_cast<const __m256i*>(p));
}

}  // namespace

bool gemm_s16_avx2_available() {
  static const bool available = __builtin_cpu_supports("avx2");
  return available;
}

__attribute__((target("avx2"))) void gemm_s16_avx2(const std::int16_t* a, int rows,
                                                   const std::int16_t* w, int cols, int depth,
                                                   std::int32_t* c) {
  const std::ptrdiff_t k_len = depth;
  const std::ptrdiff_t k_vec = depth / 16 * 16;  // the rest, and columns past cols_vec, scalar
  const int cols_vec = cols / 4 * 4;
  auto tail = [&](int row, int j) {
    std::int32_t s = 0;
    for (std::ptrdiff_t k = k_vec; k < k_len; ++k) s += a[row * k_len + k] * w[j * k_len + k];
    return s;
  };
  auto dot = [&](int row, int j) {
    std::int32_t s = 0;
    for (std::ptrdiff_t k = 0; k < k_len; ++k) s += a[row * k_len + k] * w[j * k_len + k];
    return s;
  };
  int m = 0;
  for (; m + 2 <= rows; m += 2) {
    const std::int16_t* a0 = a + m * k_len;
    const std::int16_t* a1 = a0 + k_len;
    for (int j = 0; j < cols_vec; j += 4) {
      const std::int16_t* w0 = w + j * k_len;
      const std::int16_t* w1 = w0 + k_len;
      const std::int16_t* w2 = w1 + k_len;
      const std::int16_t* w3 = w2 + k_len;
      __m256i c00 = _mm256_setzero_si256(), c01 = c00, c02 = c00, c03 = c00;
      __m256i c10 = c00, c11 = c00, c12 = c00, c13 = c00;
      for (std::ptrdiff_t k = 0; k < k_vec; k += 16) {
        const __m256i x0 = load(a0 + k);
        const __m256i x1 = load(a1 + k);
        __m256i v = load(w0 + k);
        c00 = _mm256_add_epi32(c00, _mm256_madd_epi16(x0, v));
        c10 = _mm256_add_epi32(c10, _mm256_madd_epi16(x1, v));
        v = load(w1 + k);
        c01 = _mm256_add_epi32(c01, _mm256_madd_epi16(x0, v));
        c11 = _mm256_add_epi32(c11, _mm256_madd_epi16(x1, v));
        v = load(w2 + k);
        c02 = _mm256_add_epi32(c02, _mm256_madd_epi16(x0, v));
        c12 = _mm256_add_epi32(c12, _mm256_madd_epi16(x1, v));
        v = load(w3 + k);
        c03 = _mm256_add_epi32(c03, _mm256_madd_epi16(x0, v));
        c13 = _mm256_add_epi32(c13, _mm256_madd_epi16(x1, v));
      }
      _mm_storeu_si128(reinterpret_cast<__m128i*>(c + m * cols + j), sum4(c00, c01, c02, c03));
      _mm_storeu_si128(reinterpret_cast<__m128i*>(c + (m + 1) * cols + j),
                       sum4(c10, c11, c12, c13));
      for (int r = m; r < m + 2; ++r) {
        for (int jj = j; jj < j + 4; ++jj) c[r * cols + jj] += tail(r, jj);
      }
    }
    for (int r = m; r < m + 2; ++r) {
      for (int j = cols_vec; j < cols; ++j) c[r * cols + j] = dot(r, j);
    }
  }
  for (; m < rows; ++m) {
    const std::int16_t* a0 = a + m * k_len;
    for (int j = 0; j < cols_vec; j += 4) {
      const std::int16_t* w0 = w + j * k_len;
      __m256i c0 = _mm256_setzero_si256(), c1 = c0, c2 = c0, c3 = c0;
      for (std::ptrdiff_t k = 0; k < k_vec; k += 16) {
        const __m256i x0 = load(a0 + k);
        c0 = _mm256_add_epi32(c0, _mm256_madd_epi16(x0, load(w0 + k)));
        c1 = _mm256_add_epi32(c1, _mm256_madd_epi16(x0, load(w0 + k_len + k)));
        c2 = _mm256_add_epi32(c2, _mm256_madd_epi16(x0, load(w0 + 2 * k_len + k)));
        c3 = _mm256_add_epi32(c3, _mm256_madd_epi16(x0, load(w0 + 3 * k_len + k)));
      }
      _mm_storeu_si128(reinterpret_cast<__m128i*>(c + m * cols + j), sum4(c0, c1, c2, c3));
      for (int jj = j; jj < j + 4; ++jj) c[m * cols + jj] += tail(m, jj);
    }
    for (int j = cols_vec; j < cols; ++j) c[m * cols + j] = dot(m, j);
  }
}

#else

bool gemm_s16_avx2_available() { return false; }

void gemm_s16_avx2(const std::int16_t*, int, const std::int16_t*, int, int, std::int32_t*) {
  throw std::logic_error("kws: the AVX2 kernel is not compiled in");
}

#endif

}  // namespace marvin::perception::kws
