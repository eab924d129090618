// The network's arithmetic against straightforward loops written from the definition in
// network.h, float and int8, and int8 against float within the quantisation bound.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <tuple>
#include <vector>

#include "perception/kws/network.h"

namespace kws = marvin::perception::kws;

namespace {

kws::FloatNetwork random_network(std::uint64_t seed, float weight_scale) {
  kws::FloatNetwork net = kws::make_initialised_network(seed);
  std::mt19937_64 rng(seed + 1);
  std::uniform_real_distribution<float> b(-0.1f, 0.1f);
  for (kws::FloatLayer* l : net.layers()) {
    for (float& w : l->weights) w *= weight_scale;
    for (float& v : l->bias) v = b(rng);
  }
  return net;
}

std::vector<float> random_input(std::mt19937_64& rng) {
  std::normal_distribution<float> g(0.0f, 1.0f);
  std::vector<float> x(kws::kInputSize);
  for (float& v : x) v = g(rng);
  return x;
}

float w_at(const kws::FloatLayer& l, int o, int i) {
  return l.weights[static_cast<std::size_t>(o * l.in + i)];
}

// The network written out as the paper describes it, one loop per index.
std::vector<float> reference_logits(const kws::FloatNetwork& n, const std::vector<float>& x) {
  using namespace kws;
  auto in = [&](int t, int f) { return x[static_cast<std::size_t>(t * kBins + f)]; };
  std::vector<float> a1(static_cast<std::size_t>(kConv1OutTime * kPooledFreq * kConv1Maps));
  for (int c = 0; c < kConv1Maps; ++c) {
    for (int t = 0; t < kConv1OutTime; ++t) {
      for (int g = 0; g < kPooledFreq; ++g) {
        float best = -1e30f;
        for (int p = 0; p < kPoolFreq; ++p) {
          const int f = g * kPoolFreq + p;
          float s = n.conv1.bias[static_cast<std::size_t>(c)];
          for (int dt = 0; dt < kConv1Time; ++dt) {
            for (int df = 0; df < kConv1Freq; ++df) s += in(t + dt, f + df) * w_at(n.conv1, c, dt * kConv1Freq + df);
          }
          best = std::max(best, s);
        }
        a1[static_cast<std::size_t>((t * kPooledFreq + g) * kConv1Maps + c)] = std::max(0.0f, best);
      }
    }
  }
  std::vector<float> a2(kFlat);
  for (int c = 0; c < kConv2Maps; ++c) {
    for (int t = 0; t < kConv2OutTime; ++t) {
      for (int f = 0; f < kConv2OutFreq; ++f) {
        float s = n.conv2.bias[static_cast<std::size_t>(c)];
        for (int dt = 0; dt < kConv2Time; ++dt) {
          for (int df = 0; df < kConv2Freq; ++df) {
            for (int ic = 0; ic < kConv1Maps; ++ic) {
              s += a1[static_cast<std::size_t>(((t + dt) * kPooledFreq + f + df) * kConv1Maps + ic)] *
                   w_at(n.conv2, c, (dt * kConv2Freq + df) * kConv1Maps + ic);
            }
          }
        }
        a2[static_cast<std::size_t>((t * kConv2OutFreq + f) * kConv2Maps + c)] = std::max(0.0f, s);
      }
    }
  }
  auto fc = [](const kws::FloatLayer& l, const std::vector<float>& v, bool relu) {
    std::vector<float> y(static_cast<std::size_t>(l.out));
    for (int o = 0; o < l.out; ++o) {
      double s = l.bias[static_cast<std::size_t>(o)];
      for (int i = 0; i < l.in; ++i) s += static_cast<double>(v[static_cast<std::size_t>(i)]) * w_at(l, o, i);
      y[static_cast<std::size_t>(o)] = relu ? std::max(0.0f, static_cast<float>(s)) : static_cast<float>(s);
    }
    return y;
  };
  return fc(n.output, fc(n.dense, fc(n.linear, a2, false), true), false);
}

std::vector<float> softmaxed(std::vector<float> v) {
  kws::softmax(v);
  return v;
}

}  // namespace

TEST_CASE("shapes: about 245 K parameters") {
  const kws::FloatNetwork net = kws::make_initialised_network(1);
  CHECK(net.parameter_count() == 10240 + 64 + 163840 + 64 + 65536 + 32 + 4096 + 128 + 512 + 4);
}

TEST_CASE("float inference equals the reference loops") {
  const kws::FloatNetwork net = random_network(7, 0.5f);
  kws::FloatInference inference(net);
  std::mt19937_64 rng(3);
  for (int trial = 0; trial < 3; ++trial) {
    const std::vector<float> x = random_input(rng);
    const std::vector<float> ref = softmaxed(reference_logits(net, x));
    std::vector<float> got(kws::kClasses);
    inference.run(x, got);
    REQUIRE(*std::max_element(ref.begin(), ref.end()) < 0.999f);  // not saturated
    for (int c = 0; c < kws::kClasses; ++c) CHECK(got[static_cast<std::size_t>(c)] == doctest::Approx(ref[static_cast<std::size_t>(c)]).epsilon(1e-3));
  }
}

TEST_CASE("the AVX2 and portable int8 kernels give identical sums") {
  std::mt19937_64 rng(5);
  std::uniform_int_distribution<int> q(-127, 127);
  for (auto [rows, cols, depth] : {std::tuple{429, 64, 160}, std::tuple{3, 8, 32}, std::tuple{1, 4, 2048}}) {
    std::vector<std::int16_t> a(static_cast<std::size_t>(rows * depth)), w(static_cast<std::size_t>(cols * depth));
    for (auto& v : a) v = static_cast<std::int16_t>(q(rng));
    for (auto& v : w) v = static_cast<std::int16_t>(q(rng));
    std::vector<std::int32_t> ref(static_cast<std::size_t>(rows * cols)), got(ref.size());
    // Reference written independently of both kernels.
    for (int m = 0; m < rows; ++m) {
      for (int j = 0; j < cols; ++j) {
        std::int64_t s = 0;
        for (int k = 0; k < depth; ++k) s += a[static_cast<std::size_t>(m * depth + k)] * w[static_cast<std::size_t>(j * depth + k)];
        ref[static_cast<std::size_t>(m * cols + j)] = static_cast<std::int32_t>(s);
      }
    }
    kws::gemm_s16_portable(a.data(), rows, w.data(), cols, depth, got.data());
    CHECK(got == ref);
    if (kws::gemm_s16_avx2_available()) {
      std::fill(got.begin(), got.end(), 0);
      kws::gemm_s16_avx2(a.data(), rows, w.data(), cols, depth, got.data());
      CHECK(got == ref);
    }
  }
}

TEST_CASE("int8 layer against float within the quantisation bound") {
  // y = W x in float vs s_x s_w[o] * sum(q(x) q(w)) in int8 x int8 -> int32. With rounding
  // errors |dx| <= s_x/2 and |dw| <= s_w/2 per element:
  //   |y - y_q| <= sum_i |w_i| s_x/2 + |x_i| s_w/2 + s_x s_w / 4.
  std::mt19937_64 rng(11);
  std::normal_distribution<float> g(0.0f, 1.0f);
  for (auto scaling : {kws::WeightScaling::per_channel, kws::WeightScaling::per_tensor}) {
    kws::FloatLayer layer{32, 256, std::vector<float>(32 * 256), std::vector<float>(32, 0.0f)};
    for (int o = 0; o < 32; ++o) {
      for (int i = 0; i < 256; ++i) layer.weights[static_cast<std::size_t>(o * 256 + i)] = g(rng) * (0.1f + 0.05f * static_cast<float>(o));
    }
    const kws::QuantizedLayer q = kws::quantize_layer(layer, scaling);
    std::vector<float> x(256);
    for (float& v : x) v = g(rng);
    float xmax = 0.0f;
    for (float v : x) xmax = std::max(xmax, std::fabs(v));
    const float sx = xmax / 127.0f;
    std::vector<std::int16_t> xq(256), wq(q.weights.begin(), q.weights.end());
    for (std::size_t i = 0; i < 256; ++i) xq[i] = static_cast<std::int16_t>(std::nearbyint(x[i] / sx));
    std::vector<std::int32_t> acc(32);
    kws::gemm_s16_portable(xq.data(), 1, wq.data(), 32, 256, acc.data());
    for (int o = 0; o < 32; ++o) {
      const float sw = q.weight_scales[static_cast<std::size_t>(o)];
      double y = 0.0, bound = 0.0;
      for (int i = 0; i < 256; ++i) {
        const float w = layer.weights[static_cast<std::size_t>(o * 256 + i)];
        y += static_cast<double>(w) * x[static_cast<std::size_t>(i)];
        bound += std::fabs(w) * sx / 2 + std::fabs(x[static_cast<std::size_t>(i)]) * sw / 2 + sx * sw / 4;
      }
      const double yq = static_cast<double>(acc[static_cast<std::size_t>(o)]) * sx * sw;
      CHECK(std::fabs(y - yq) <= bound * 1.0001 + 1e-6);
      CHECK(std::fabs(y - yq) > 0.0);  // it really is quantised
    }
    if (scaling == kws::WeightScaling::per_tensor) {
      CHECK(q.weight_scales.front() == q.weight_scales.back());
    } else {
      CHECK(q.weight_scales.front() < q.weight_scales.back());
    }
  }
}

TEST_CASE("int8 network agrees with float on random inputs") {
  const kws::FloatNetwork net = random_network(21, 0.6f);
  std::mt19937_64 rng(4);
  std::vector<std::vector<float>> inputs;
  for (int i = 0; i < 40; ++i) inputs.push_back(random_input(rng));
  // Calibrate: largest activations over the inputs.
  kws::FloatInference fi(net);
  kws::ActivationScales s;
  std::vector<float> p(kws::kClasses);
  for (const auto& x : inputs) {
    fi.run(x, p);
    const auto& r = fi.last_ranges();
    s.input = std::max(s.input, r.input / 127.0f);
    s.conv1 = std::max(s.conv1, r.conv1 / 127.0f);
    s.conv2 = std::max(s.conv2, r.conv2 / 127.0f);
    s.linear = std::max(s.linear, r.linear / 127.0f);
    s.dense = std::max(s.dense, r.dense / 127.0f);
  }
  const kws::QuantizedNetwork q = kws::quantize(net, s);
  kws::Int8Inference ii(q);
  kws::Int8Inference portable(q);
  portable.set_portable(true);
  int agree = 0;
  double worst = 0.0;
  std::vector<float> pf(kws::kClasses), pq(kws::kClasses), pp(kws::kClasses);
  for (const auto& x : inputs) {
    fi.run(x, pf);
    ii.run(x, pq);
    portable.run(x, pp);
    CHECK(pq == pp);  // both kernels, bit for bit
    for (int c = 0; c < kws::kClasses; ++c) worst = std::max(worst, static_cast<double>(std::fabs(pf[static_cast<std::size_t>(c)] - pq[static_cast<std::size_t>(c)])));
    if (std::max_element(pf.begin(), pf.end()) - pf.begin() == std::max_element(pq.begin(), pq.end()) - pq.begin()) ++agree;
  }
  CHECK(worst < 0.1);
  CHECK(agree >= 36);
}
