// Every int8 kernel this CPU has (portable, AVX2, AVX-512 VNNI) against one reference loop on
// random int8 data, including sizes that are not whole vector blocks, the byte kernels at the
// values where vpmaddubsw would saturate, the packed kernels reading a convolution's input in
// place (fused im2col), and the whole int8 network with each kernel bit for bit. Kernels the
// CPU lacks are skipped with a MESSAGE.
#include <doctest/doctest.h>

#include <algorithm>
#include <cstdint>
#include <random>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

#include "perception/kws/network.h"

namespace kws = marvin::perception::kws;

namespace {

using Kernel = void (*)(const std::int16_t*, int, const std::int16_t*, int, int, std::int32_t*);

struct NamedKernel {
  kws::Int8Kernel id;
  Kernel run;
};

const NamedKernel kKernels[] = {
    {kws::Int8Kernel::portable, kws::gemm_s16_portable},
    {kws::Int8Kernel::avx2, kws::gemm_s16_avx2},
    {kws::Int8Kernel::avx512_vnni, kws::gemm_s16_avx512},
};

std::vector<std::int16_t> random_int8(std::size_t n, std::mt19937_64& rng) {
  std::uniform_int_distribution<int> q(-127, 127);
  std::vector<std::int16_t> v(n);
  for (auto& x : v) x = static_cast<std::int16_t>(q(rng));
  return v;
}

// c[m][j] = sum_i a[m][i] * w[j][i], the plain loops every kernel must match exactly.
template <typename A>
std::vector<std::int32_t> reference_gemm(const std::vector<A>& a, int rows,
                                         const std::vector<std::int16_t>& w, int cols, int depth) {
  std::vector<std::int32_t> c(static_cast<std::size_t>(rows) * cols);
  for (int m = 0; m < rows; ++m) {
    for (int j = 0; j < cols; ++j) {
      std::int64_t s = 0;
      for (int i = 0; i < depth; ++i) {
        s +=
            a[static_cast<std::size_t>(m) * depth + i] * w[static_cast<std::size_t>(j) * depth + i];
      }
      c[static_cast<std::size_t>(m) * cols + j] = static_cast<std::int32_t>(s);
    }
  }
  return c;
}

}  // namespace

TEST_CASE("every available int8 kernel gives exactly the reference sums, odd sizes too") {
  std::mt19937_64 rng(17);
  // (rows, cols, depth): the network's layers, then sizes that leave remainders everywhere
  // (rows not a multiple of 2 or 6, cols not of 4 or 16, depth odd or not a multiple of 16).
  const std::tuple<int, int, int> shapes[] = {
      {429, 64, 160}, {32, 64, 2560}, {1, 32, 2048}, {1, 128, 32},   {1, 4, 128},
      {7, 5, 33},     {13, 19, 1},    {1, 1, 1},     {11, 67, 2561}, {5, 17, 47},
  };
  for (const NamedKernel& k : kKernels) {
    if (!kws::kernel_available(k.id)) {
      MESSAGE("skipped: this CPU or build has no " << kws::kernel_name(k.id) << " kernel");
      continue;
    }
    for (auto [rows, cols, depth] : shapes) {
      CAPTURE(kws::kernel_name(k.id));
      CAPTURE(rows);
      CAPTURE(cols);
      CAPTURE(depth);
      const auto a = random_int8(static_cast<std::size_t>(rows) * depth, rng);
      const auto w = random_int8(static_cast<std::size_t>(cols) * depth, rng);
      const std::vector<std::int32_t> ref = reference_gemm(a, rows, w, cols, depth);
      // A guard past the end shows a kernel writing outside its rows x cols.
      std::vector<std::int32_t> got(ref.size() + 16, -1);
      k.run(a.data(), rows, w.data(), cols, depth, got.data());
      CHECK(std::vector<std::int32_t>(
                got.begin(), got.begin() + static_cast<std::ptrdiff_t>(ref.size())) == ref);
      CHECK(std::vector<std::int32_t>(got.end() - 16, got.end()) ==
            std::vector<std::int32_t>(16, -1));
    }
  }
}

TEST_CASE("the AVX-512 byte kernel gives exactly the reference sums for unsigned activations") {
  if (!kws::gemm_s16_avx512_available()) {
    MESSAGE("skipped: this CPU or build has no AVX-512 VNNI kernel");
    return;
  }
  std::mt19937_64 rng(23);
  std::uniform_int_distribution<int> u(0, 255);
  // Depths that are not whole groups of 4 (1, 2, 3 left over) and cols not of 16.
  const std::tuple<int, int, int> shapes[] = {
      {32, 64, 2560}, {1, 32, 2048},  {7, 5, 33}, {13, 19, 2},
      {6, 17, 47},    {11, 67, 2563}, {1, 1, 1},
  };
  for (auto [rows, cols, depth] : shapes) {
    CAPTURE(rows);
    CAPTURE(cols);
    CAPTURE(depth);
    std::vector<std::uint8_t> a(static_cast<std::size_t>(rows) * depth);
    for (auto& x : a) x = static_cast<std::uint8_t>(u(rng));
    const auto w = random_int8(static_cast<std::size_t>(cols) * depth, rng);
    const std::vector<std::int32_t> ref = reference_gemm(a, rows, w, cols, depth);
    std::vector<std::int32_t> got(ref.size() + 16, -1);
    kws::gemm_u8s8_avx512(a.data(), rows, w.data(), cols, depth, got.data());
    CHECK(std::vector<std::int32_t>(got.begin(),
                                    got.begin() + static_cast<std::ptrdiff_t>(ref.size())) == ref);
    CHECK(std::vector<std::int32_t>(got.end() - 16, got.end()) ==
          std::vector<std::int32_t>(16, -1));
  }
}

TEST_CASE("the AVX2 byte kernel is exact for activations 0..127, at the saturation edge too") {
  if (!kws::gemm_s16_avx2_available()) {
    MESSAGE("skipped: this CPU or build has no AVX2 kernel");
    return;
  }
  std::mt19937_64 rng(29);
  std::uniform_int_distribution<int> u(0, 127);
  std::uniform_int_distribution<int> s8(-128, 127);
  // Depths not whole groups of 4, cols not whole blocks of 8, rows not whole blocks of 4.
  const std::tuple<int, int, int> shapes[] = {
      {32, 64, 2560}, {1, 32, 2048}, {7, 5, 33}, {13, 19, 2}, {6, 17, 47},
      {11, 67, 2563}, {1, 1, 1},     {5, 9, 3},  {4, 8, 4},
  };
  for (auto [rows, cols, depth] : shapes) {
    CAPTURE(rows);
    CAPTURE(cols);
    CAPTURE(depth);
    std::vector<std::uint8_t> a(static_cast<std::size_t>(rows) * depth);
    for (auto& x : a) x = static_cast<std::uint8_t>(u(rng));
    std::vector<std::int16_t> w(static_cast<std::size_t>(cols) * depth);
    for (auto& x : w) x = static_cast<std::int16_t>(s8(rng));
    const std::vector<std::int32_t> ref = reference_gemm(a, rows, w, cols, depth);
    std::vector<std::int32_t> got(ref.size() + 16, -1);
    kws::gemm_u8s8_avx2(a.data(), rows, w.data(), cols, depth, got.data());
    CHECK(std::vector<std::int32_t>(got.begin(),
                                    got.begin() + static_cast<std::ptrdiff_t>(ref.size())) == ref);
    CHECK(std::vector<std::int32_t>(got.end() - 16, got.end()) ==
          std::vector<std::int32_t>(16, -1));
  }
  // The largest pair sums vpmaddubsw forms: 127 x 127 + 127 x 127 = 32258 and
  // 127 x -128 + 127 x -128 = -32512, next to the int16 limits; every row of the sums is them.
  for (int weight : {127, -128, -127}) {
    CAPTURE(weight);
    const int rows = 5, cols = 9, depth = 64;
    const std::vector<std::uint8_t> a(static_cast<std::size_t>(rows) * depth, 127);
    const std::vector<std::int16_t> w(static_cast<std::size_t>(cols) * depth,
                                      static_cast<std::int16_t>(weight));
    std::vector<std::int32_t> got(static_cast<std::size_t>(rows) * cols, -1);
    kws::gemm_u8s8_avx2(a.data(), rows, w.data(), cols, depth, got.data());
    CHECK(got == std::vector<std::int32_t>(got.size(), 127 * weight * depth));
  }
}

TEST_CASE("the int16 kernels are exact at the extremes of int8") {
  // vpmaddwd's one overflow (-32768 x -32768 twice) is outside int8; its int8 extremes are not.
  for (const NamedKernel& k : kKernels) {
    if (!kws::kernel_available(k.id)) continue;
    CAPTURE(kws::kernel_name(k.id));
    for (int value : {-128, 127}) {
      const int rows = 7, cols = 11, depth = 161;
      const std::vector<std::int16_t> a(static_cast<std::size_t>(rows) * depth,
                                        static_cast<std::int16_t>(value));
      const std::vector<std::int16_t> w(static_cast<std::size_t>(cols) * depth, -128);
      std::vector<std::int32_t> got(static_cast<std::size_t>(rows) * cols, -1);
      k.run(a.data(), rows, w.data(), cols, depth, got.data());
      CHECK(got == std::vector<std::int32_t>(got.size(), value * -128 * depth));
    }
  }
}

namespace {

// A convolution's input read in place: rows start at `offsets`, each made of `segments`
// segments of `seg_len` values `seg_stride` apart; the same matrix copied out (im2col).
template <typename A>
std::vector<A> copy_rows(const std::vector<A>& base, const std::vector<std::int32_t>& offsets,
                         int segments, int seg_len, int seg_stride) {
  std::vector<A> out;
  for (std::int32_t o : offsets) {
    for (int s = 0; s < segments; ++s) {
      for (int i = 0; i < seg_len; ++i) {
        out.push_back(base.at(static_cast<std::size_t>(o + s * seg_stride + i)));
      }
    }
  }
  return out;
}

}  // namespace

TEST_CASE("the AVX2 packed kernels read a convolution's input in place exactly") {
  if (!kws::gemm_s16_avx2_available()) {
    MESSAGE("skipped: this CPU or build has no AVX2 kernel");
    return;
  }
  std::mt19937_64 rng(41);
  std::uniform_int_distribution<int> u(0, 127);
  // (out time, out freq, kernel time, kernel freq x channels, input freq x channels, step
  // between output freqs, output channels): conv1 and conv2 of the network, then odd shapes
  // (rows not whole blocks of 6 or 4, cols 5 and 19).
  struct Conv {
    int out_t, out_f, k_t, seg_len, row_len, f_step, cols;
  };
  const Conv convs[] = {{13, 33, 20, 8, 40, 1, 64},
                        {4, 8, 10, 256, 704, 64, 64},
                        {3, 5, 3, 4, 12, 2, 5},
                        {5, 3, 2, 12, 20, 4, 19}};
  for (const Conv& cv : convs) {
    CAPTURE(cv.seg_len);
    CAPTURE(cv.cols);
    REQUIRE((cv.out_f - 1) * cv.f_step + cv.seg_len <= cv.row_len);
    const int in_t = cv.out_t + cv.k_t - 1;
    const int depth = cv.k_t * cv.seg_len;
    std::vector<std::int32_t> offsets;
    for (int t = 0; t < cv.out_t; ++t) {
      for (int f = 0; f < cv.out_f; ++f) offsets.push_back(t * cv.row_len + f * cv.f_step);
    }
    const int rows = static_cast<int>(offsets.size());
    const auto w = random_int8(static_cast<std::size_t>(cv.cols) * depth, rng);
    const auto s16 = random_int8(static_cast<std::size_t>(in_t) * cv.row_len, rng);
    std::vector<std::uint8_t> u8(s16.size());
    for (auto& x : u8) x = static_cast<std::uint8_t>(u(rng));

    const auto ref16 = reference_gemm(copy_rows(s16, offsets, cv.k_t, cv.seg_len, cv.row_len), rows,
                                      w, cv.cols, depth);
    std::vector<std::int32_t> got(ref16.size(), -1);
    kws::detail::gemm_avx2_packed(kws::detail::RowsView<std::int16_t>{s16.data(), offsets.data(),
                                                                      rows, cv.seg_len, cv.row_len},
                                  kws::detail::pack_weights_s16_avx2(w.data(), cv.cols, depth),
                                  got.data());
    CHECK(got == ref16);

    const auto ref8 = reference_gemm(copy_rows(u8, offsets, cv.k_t, cv.seg_len, cv.row_len), rows,
                                     w, cv.cols, depth);
    std::fill(got.begin(), got.end(), -1);
    kws::detail::gemm_avx2_packed(kws::detail::RowsView<std::uint8_t>{u8.data(), offsets.data(),
                                                                      rows, cv.seg_len, cv.row_len},
                                  kws::detail::pack_weights_s8_avx2(w.data(), cv.cols, depth),
                                  got.data());
    CHECK(got == ref8);
  }
  // Segments that are not whole groups (and not the whole depth) cannot be packed: refused.
  const std::vector<std::uint8_t> a(64, 1);
  const std::vector<std::int32_t> offsets = {0};
  const auto w = random_int8(8 * 6, rng);
  std::vector<std::int32_t> c(8);
  try {
    kws::detail::gemm_avx2_packed(
        kws::detail::RowsView<std::uint8_t>{a.data(), offsets.data(), 1, 3, 8},
        kws::detail::pack_weights_s8_avx2(w.data(), 8, 6), c.data());
    FAIL("a view with segments of 3 bytes was accepted");
  } catch (const std::invalid_argument& e) {
    CHECK(std::string(e.what()).find("segments of 3 must be whole groups of 4") !=
          std::string::npos);
  }
}

TEST_CASE("the int8 network gives bit-identical probabilities with every available kernel") {
  kws::FloatNetwork net = kws::make_initialised_network(31);
  std::mt19937_64 rng(8);
  std::uniform_real_distribution<float> b(-0.2f, 0.2f);
  for (kws::FloatLayer* l : net.layers()) {
    for (float& v : l->bias) v = b(rng);
  }
  kws::ActivationScales s{3.0f / 127, 4.0f / 127, 4.0f / 127, 6.0f / 127, 6.0f / 127};
  const kws::QuantizedNetwork q = kws::quantize(net, s);
  kws::Int8Inference portable(q);
  portable.set_kernel(kws::Int8Kernel::portable);
  CHECK_FALSE(portable.vectorised());
  std::normal_distribution<float> g(0.0f, 1.0f);
  std::vector<std::vector<float>> inputs(8, std::vector<float>(kws::kInputSize));
  for (auto& x : inputs) {
    for (float& v : x) v = 4.0f * g(rng);  // some beyond the input scale: clamping too
  }
  for (kws::Int8Kernel id : {kws::Int8Kernel::avx2, kws::Int8Kernel::avx512_vnni}) {
    if (!kws::kernel_available(id)) {
      MESSAGE("skipped: this CPU or build has no " << kws::kernel_name(id) << " kernel");
      continue;
    }
    CAPTURE(kws::kernel_name(id));
    kws::Int8Inference fast(q);
    fast.set_kernel(id);
    CHECK(fast.kernel() == id);
    std::vector<std::vector<float>> seen;
    for (const auto& x : inputs) {
      std::vector<float> pp(kws::kClasses), pf(kws::kClasses);
      portable.run(x, pp);
      fast.run(x, pf);
      CHECK(pf == pp);
      seen.push_back(pp);
    }
    // The outputs depend on the input (not saturated or dead), so equality means something.
    CHECK(std::count(seen.begin(), seen.end(), seen.front()) == 1);
  }
}

TEST_CASE("the fastest kernel is the default and unavailable kernels are refused") {
  kws::QuantizedNetwork q =
      kws::quantize(kws::make_initialised_network(2), {0.01f, 0.01f, 0.01f, 0.01f, 0.01f});
  kws::Int8Inference inference(q);
  CHECK(inference.kernel() == kws::best_int8_kernel());
  CHECK(kws::kernel_available(kws::Int8Kernel::portable));
  for (kws::Int8Kernel id : {kws::Int8Kernel::avx2, kws::Int8Kernel::avx512_vnni}) {
    if (kws::kernel_available(id)) continue;
    const kws::Int8Kernel before = inference.kernel();
    try {
      inference.set_kernel(id);
      FAIL("set_kernel accepted a kernel the CPU lacks");
    } catch (const std::invalid_argument& e) {
      CHECK(std::string(e.what()).find(kws::kernel_name(id)) != std::string::npos);
    }
    CHECK(inference.kernel() == before);
  }
  inference.set_portable(true);
  CHECK(inference.kernel() == kws::Int8Kernel::portable);
  inference.set_portable(false);
  CHECK(inference.kernel() == kws::best_int8_kernel());
}
