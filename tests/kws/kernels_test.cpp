// Every int8 kernel this CPU has (portable, AVX2, AVX-512 VNNI) against one reference loop on
// random int8 data, including sizes that are not whole vector blocks, and the whole int8
// network with each kernel bit for bit. Kernels the CPU lacks are skipped with a MESSAGE.
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
        s += a[static_cast<std::size_t>(m) * depth + i] *
             w[static_cast<std::size_t>(j) * depth + i];
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
      {429, 64, 160}, {32, 64, 2560}, {1, 32, 2048}, {1, 128, 32}, {1, 4, 128},
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
      {32, 64, 2560}, {1, 32, 2048}, {7, 5, 33},  {13, 19, 2},
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
    CHECK(std::vector<std::int32_t>(
                got.begin(), got.begin() + static_cast<std::ptrdiff_t>(ref.size())) == ref);
    CHECK(std::vector<std::int32_t>(got.end() - 16, got.end()) ==
            std::vector<std::int32_t>(16, -1));
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
  kws::QuantizedNetwork q = kws::quantize(kws::make_initialised_network(2),
                                          {0.01f, 0.01f, 0.01f, 0.01f, 0.01f});
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
