#include "perception/kws/network.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <stdexcept>

#include "perception/kws/im2col.h"

namespace marvin::perception::kws {

namespace {

using RowMatrix = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
using MatrixMap = Eigen::Map<RowMatrix>;
using ConstMatrixMap = Eigen::Map<const RowMatrix>;

float max_abs(std::span<const float> values) {
  float m = 0.0f;
  for (float v : values) m = std::max(m, std::fabs(v));
  return m;
}

void check_layer(const FloatLayer& layer, const char* name, int out, int in) {
  if (layer.out != out || layer.in != in ||
      layer.weights.size() != static_cast<std::size_t>(out) * static_cast<std::size_t>(in) ||
      layer.bias.size() != static_cast<std::size_t>(out)) {
    throw std::invalid_argument(std::string("kws network: layer ") + name + " must be " +
                                std::to_string(out) + "x" + std::to_string(in));
  }
}

void check_network(const FloatNetwork& net) {
  check_layer(net.conv1, "conv1", kConv1Maps, kConv1In);
  check_layer(net.conv2, "conv2", kConv2Maps, kConv2In);
  check_layer(net.linear, "linear", kLinear, kFlat);
  check_layer(net.dense, "dense", kDense, kLinear);
  check_layer(net.output, "output", kClasses, kDense);
}

}  // namespace

const char* class_name(int cls) {
  switch (cls) {
    case 0:
      return "keyword";
    case 1:
      return "unknown";
    case 2:
      return "silence";
    case 3:
      return "noise";
    default:
      return "?";
  }
}

std::size_t FloatNetwork::parameter_count() const {
  std::size_t n = 0;
  for (const FloatLayer* l : layers()) n += l->weights.size() + l->bias.size();
  return n;
}

FloatNetwork make_initialised_network(std::uint64_t seed) {
  FloatNetwork net;
  std::mt19937_64 rng(seed);
  for (FloatLayer* l : net.layers()) {
    const float limit = std::sqrt(6.0f / static_cast<float>(l->in));
    std::uniform_real_distribution<float> dist(-limit, limit);
    l->weights.resize(static_cast<std::size_t>(l->out) * static_cast<std::size_t>(l->in));
    for (float& w : l->weights) w = dist(rng);
    l->bias.assign(static_cast<std::size_t>(l->out), 0.0f);
  }
  return net;
}

QuantizedLayer quantize_layer(const FloatLayer& layer, WeightScaling scaling) {
  QuantizedLayer q;
  q.out = layer.out;
  q.in = layer.in;
  q.bias = layer.bias;
  q.weights.resize(layer.weights.size());
  q.weight_scales.resize(static_cast<std::size_t>(layer.out));
  const float tensor_max = max_abs(layer.weights);
  for (int o = 0; o < layer.out; ++o) {
    std::span<const float> row(layer.weights.data() + static_cast<std::size_t>(o) * layer.in,
                               static_cast<std::size_t>(layer.in));
    float m = scaling == WeightScaling::per_channel ? max_abs(row) : tensor_max;
    const float scale = m > 0.0f ? m / 127.0f : 1.0f;
    q.weight_scales[static_cast<std::size_t>(o)] = scale;
    for (int i = 0; i < layer.in; ++i) {
      const float v = std::nearbyint(row[static_cast<std::size_t>(i)] / scale);
      q.weights[static_cast<std::size_t>(o) * layer.in + i] =
          static_cast<std::int8_t>(std::clamp(v, -127.0f, 127.0f));
    }
  }
  return q;
}

FloatLayer dequantize_layer(const QuantizedLayer& layer) {
  FloatLayer f;
  f.out = layer.out;
  f.in = layer.in;
  f.bias = layer.bias;
  f.weights.resize(layer.weights.size());
  for (int o = 0; o < layer.out; ++o) {
    for (int i = 0; i < layer.in; ++i) {
      const std::size_t k = static_cast<std::size_t>(o) * layer.in + i;
      f.weights[k] =
          static_cast<float>(layer.weights[k]) * layer.weight_scales[static_cast<std::size_t>(o)];
    }
  }
  return f;
}

QuantizedNetwork quantize(const FloatNetwork& net, const ActivationScales& scales,
                          WeightScaling scaling) {
  check_network(net);
  QuantizedNetwork q;
  auto src = net.layers();
  auto dst = q.layers();
  for (std::size_t i = 0; i < src.size(); ++i) *dst[i] = quantize_layer(*src[i], scaling);
  q.scales = scales;
  return q;
}

FloatNetwork dequantize(const QuantizedNetwork& net) {
  FloatNetwork f;
  auto src = net.layers();
  auto dst = f.layers();
  for (std::size_t i = 0; i < src.size(); ++i) *dst[i] = dequantize_layer(*src[i]);
  return f;
}

void softmax(std::span<float> values) {
  float m = values[0];
  for (float v : values) m = std::max(m, v);
  float sum = 0.0f;
  for (float& v : values) {
    v = std::exp(v - m);
    sum += v;
  }
  for (float& v : values) v /= sum;
}

// ---- float ------------------------------------------------------------------------------

FloatInference::FloatInference(const FloatNetwork& net) : net_(net) {
  check_network(net_);
  cols1_.resize(static_cast<std::size_t>(kConv1OutTime * kConv1OutFreq * kConv1In));
  z1_.resize(static_cast<std::size_t>(kConv1OutTime * kConv1OutFreq * kConv1Maps));
  a1_.resize(static_cast<std::size_t>(kConv1OutTime * kPooledFreq * kConv1Maps));
  cols2_.resize(static_cast<std::size_t>(kConv2OutTime * kConv2OutFreq * kConv2In));
  a2_.resize(kFlat);
  l_.resize(kLinear);
  h_.resize(kDense);
}

void FloatInference::run(std::span<const float> input, std::span<float> probabilities) {
  if (input.size() != static_cast<std::size_t>(kInputSize) ||
      probabilities.size() != static_cast<std::size_t>(kClasses)) {
    throw std::invalid_argument("kws FloatInference::run: input must hold 1280 values, output 4");
  }
  ranges_.input = max_abs(input);
  detail::im2col_conv1(input.data(), cols1_.data());
  constexpr int p1 = kConv1OutTime * kConv1OutFreq;
  MatrixMap z1(z1_.data(), p1, kConv1Maps);
  z1.noalias() = ConstMatrixMap(cols1_.data(), p1, kConv1In) *
                 ConstMatrixMap(net_.conv1.weights.data(), kConv1Maps, kConv1In).transpose();
  for (int t = 0; t < kConv1OutTime; ++t) {
    for (int g = 0; g < kPooledFreq; ++g) {
      float* out = a1_.data() + (t * kPooledFreq + g) * kConv1Maps;
      for (int c = 0; c < kConv1Maps; ++c) {
        float m = z1(t * kConv1OutFreq + g * kPoolFreq, c);
        for (int k = 1; k < kPoolFreq; ++k) {
          m = std::max(m, z1(t * kConv1OutFreq + g * kPoolFreq + k, c));
        }
        out[c] = std::max(0.0f, m + net_.conv1.bias[static_cast<std::size_t>(c)]);
      }
    }
  }
  ranges_.conv1 = max_abs(a1_);
  detail::im2col_conv2(a1_.data(), cols2_.data());
  constexpr int p2 = kConv2OutTime * kConv2OutFreq;
  MatrixMap z2(a2_.data(), p2, kConv2Maps);
  z2.noalias() = ConstMatrixMap(cols2_.data(), p2, kConv2In) *
                 ConstMatrixMap(net_.conv2.weights.data(), kConv2Maps, kConv2In).transpose();
  for (int p = 0; p < p2; ++p) {
    for (int c = 0; c < kConv2Maps; ++c) {
      z2(p, c) = std::max(0.0f, z2(p, c) + net_.conv2.bias[static_cast<std::size_t>(c)]);
    }
  }
  ranges_.conv2 = max_abs(a2_);
  auto dense_layer = [](const FloatLayer& layer, const float* in, float* out, bool relu) {
    Eigen::Map<Eigen::VectorXf> y(out, layer.out);
    y.noalias() = ConstMatrixMap(layer.weights.data(), layer.out, layer.in) *
                  Eigen::Map<const Eigen::VectorXf>(in, layer.in);
    for (int o = 0; o < layer.out; ++o) {
      y(o) += layer.bias[static_cast<std::size_t>(o)];
      if (relu) y(o) = std::max(0.0f, y(o));
    }
  };
  dense_layer(net_.linear, a2_.data(), l_.data(), false);
  ranges_.linear = max_abs(l_);
  dense_layer(net_.dense, l_.data(), h_.data(), true);
  ranges_.dense = max_abs(h_);
  dense_layer(net_.output, h_.data(), probabilities.data(), false);
  softmax(probabilities);
}

// ---- int8 -------------------------------------------------------------------------------

namespace {

std::int16_t quantize_value(float v, float inv_scale, bool relu) {
  float q = std::nearbyint(v * inv_scale);
  q = std::clamp(q, relu ? 0.0f : -127.0f, 127.0f);
  return static_cast<std::int16_t>(q);
}

}  // namespace

void gemm_s16_portable(const std::int16_t* a, int rows, const std::int16_t* w, int cols, int depth,
                       std::int32_t* c) {
  for (int m = 0; m < rows; ++m) {
    const std::int16_t* arow = a + static_cast<std::ptrdiff_t>(m) * depth;
    for (int j = 0; j < cols; ++j) {
      const std::int16_t* wrow = w + static_cast<std::ptrdiff_t>(j) * depth;
      std::int32_t sum = 0;
      for (int k = 0; k < depth; ++k) sum += static_cast<std::int32_t>(arow[k]) * wrow[k];
      c[static_cast<std::ptrdiff_t>(m) * cols + j] = sum;
    }
  }
}

const char* kernel_name(Int8Kernel kernel) {
  switch (kernel) {
    case Int8Kernel::portable:
      return "portable";
    case Int8Kernel::avx2:
      return "AVX2";
    case Int8Kernel::avx512_vnni:
      return "AVX-512 VNNI";
  }
  return "?";
}

bool kernel_available(Int8Kernel kernel) {
  switch (kernel) {
    case Int8Kernel::portable:
      return true;
    case Int8Kernel::avx2:
      return gemm_s16_avx2_available();
    case Int8Kernel::avx512_vnni:
      return gemm_s16_avx512_available();
  }
  return false;
}

Int8Kernel best_int8_kernel() {
  static const Int8Kernel best = kernel_available(Int8Kernel::avx512_vnni) ? Int8Kernel::avx512_vnni
                                 : kernel_available(Int8Kernel::avx2)      ? Int8Kernel::avx2
                                                                           : Int8Kernel::portable;
  return best;
}

Int8Inference::Int8Inference(const QuantizedNetwork& net) : scales_(net.scales) {
  const float act_in[5] = {net.scales.input, net.scales.conv1, net.scales.conv2, net.scales.linear,
                           net.scales.dense};
  auto src = net.layers();
  Layer* dst[5] = {&conv1_, &conv2_, &linear_, &dense_, &output_};
  const int shapes[5][2] = {{kConv1Maps, kConv1In},
                            {kConv2Maps, kConv2In},
                            {kLinear, kFlat},
                            {kDense, kLinear},
                            {kClasses, kDense}};
  for (std::size_t i = 0; i < 5; ++i) {
    const QuantizedLayer& q = *src[i];
    if (q.out != shapes[i][0] || q.in != shapes[i][1] ||
        q.weights.size() != static_cast<std::size_t>(q.out) * static_cast<std::size_t>(q.in) ||
        q.weight_scales.size() != static_cast<std::size_t>(q.out) ||
        q.bias.size() != static_cast<std::size_t>(q.out)) {
      throw std::invalid_argument("kws Int8Inference: layer " + std::to_string(i + 1) +
                                  " has the wrong shape");
    }
    if (!(act_in[i] > 0.0f)) {
      throw std::invalid_argument("kws Int8Inference: activation scale " + std::to_string(i) +
                                  " must be positive");
    }
    Layer& l = *dst[i];
    l.out = q.out;
    l.in = q.in;
    l.weights.assign(q.weights.begin(), q.weights.end());
    l.bias.resize(static_cast<std::size_t>(q.out));
    l.to_real.resize(static_cast<std::size_t>(q.out));
    for (std::size_t o = 0; o < static_cast<std::size_t>(q.out); ++o) {
      const float acc_scale = act_in[i] * q.weight_scales[o];
      l.to_real[o] = acc_scale;
      const double b = std::nearbyint(static_cast<double>(q.bias[o]) / acc_scale);
      l.bias[o] = static_cast<std::int32_t>(std::clamp(b, -2.0e9, 2.0e9));
    }
  }
  a1_.resize(static_cast<std::size_t>(kConv1OutTime * kPooledFreq * kConv1Maps));
  a2_.resize(kFlat);
  l_.resize(kLinear);
  h_.resize(kDense);
  acc_.resize(static_cast<std::size_t>(kConv1OutTime * kConv1OutFreq * kConv1Maps));
  for (int t = 0; t < kConv1OutTime; ++t) {
    for (int f = 0; f < kConv1OutFreq; ++f) conv1_rows_.push_back(t * kBins + f);
  }
  for (int t = 0; t < kConv2OutTime; ++t) {
    for (int f = 0; f < kConv2OutFreq; ++f) {
      conv2_rows_.push_back((t * kPooledFreq + f) * kConv1Maps);
    }
  }
  set_kernel(best_int8_kernel());
}

void Int8Inference::set_kernel(Int8Kernel kernel) {
  if (!kernel_available(kernel)) {
    throw std::invalid_argument(std::string("kws Int8Inference: the ") + kernel_name(kernel) +
                                " kernel is not available on this CPU or build");
  }
  if (kernel == Int8Kernel::avx512_vnni && conv2_bytes_.data.empty()) {
    for (Layer* l : {&linear_, &dense_, &output_}) {
      l->packed = detail::pack_weights_s16(l->weights.data(), l->out, l->in);
    }
    conv1_bytes_ = detail::pack_weights_s8(conv1_.weights.data(), conv1_.out, conv1_.in);
    conv1_shifted_bias_ = conv1_.bias;
    for (std::size_t o = 0; o < conv1_shifted_bias_.size(); ++o) {
      const std::int16_t* w = conv1_.weights.data() + o * static_cast<std::size_t>(conv1_.in);
      std::int32_t sum = 0;
      for (int k = 0; k < conv1_.in; ++k) sum += w[k];
      conv1_shifted_bias_[o] -= 128 * sum;
    }
    conv2_bytes_ = detail::pack_weights_s8(conv2_.weights.data(), conv2_.out, conv2_.in);
    a1_bytes_.resize(a1_.size());
  }
  if (kernel == Int8Kernel::avx2 && conv2_avx2_.data.empty()) {
    for (Layer* l : {&linear_, &dense_, &output_}) {
      l->packed256 = detail::pack_weights_s16_avx2(l->weights.data(), l->out, l->in);
    }
    conv1_avx2_ = detail::pack_weights_s16_avx2(conv1_.weights.data(), conv1_.out, conv1_.in);
    conv2_avx2_ = detail::pack_weights_s8_avx2(conv2_.weights.data(), conv2_.out, conv2_.in);
    a1_bytes_.resize(a1_.size());
  }
  if (kernel == Int8Kernel::portable && cols1_.empty()) {
    // The portable kernel reads im2col copies (about 300 KB); the vector kernels read the
    // frames in place, so a spotter on such a CPU never allocates them.
    cols1_.resize(static_cast<std::size_t>(kConv1OutTime * kConv1OutFreq * kConv1In));
    cols2_.resize(static_cast<std::size_t>(kConv2OutTime * kConv2OutFreq * kConv2In));
  }
  kernel_ = kernel;
}

void Int8Inference::gemm(const std::int16_t* a, int rows, const Layer& layer,
                         std::int32_t* c) const {
  gemm_s16_portable(a, rows, layer.weights.data(), layer.out, layer.in, c);
}

void Int8Inference::run(std::span<const float> input, std::span<float> probabilities) {
  if (input.size() != static_cast<std::size_t>(kInputSize) ||
      probabilities.size() != static_cast<std::size_t>(kClasses)) {
    throw std::invalid_argument("kws Int8Inference::run: input must hold 1280 values, output 4");
  }
  if (kernel_ == Int8Kernel::avx512_vnni) {
    run_avx512(input, probabilities);
    return;
  }
  if (kernel_ == Int8Kernel::avx2) {
    run_avx2(input, probabilities);
    return;
  }
  // Input -> int8, straight into conv1's columns (im2col on the quantised frame).
  std::int16_t qin[kInputSize];
  const float inv_in = 1.0f / scales_.input;
  for (int i = 0; i < kInputSize; ++i) {
    qin[i] = quantize_value(input[static_cast<std::size_t>(i)], inv_in, false);
  }
  detail::im2col_conv1(qin, cols1_.data());
  constexpr int p1 = kConv1OutTime * kConv1OutFreq;
  gemm(cols1_.data(), p1, conv1_, acc_.data());
  // Pool on the accumulators (per-channel rescale is positive, so max commutes), then bias,
  // ReLU and requantise.
  const float inv1 = 1.0f / scales_.conv1;
  for (int t = 0; t < kConv1OutTime; ++t) {
    for (int g = 0; g < kPooledFreq; ++g) {
      std::int16_t* out = a1_.data() + (t * kPooledFreq + g) * kConv1Maps;
      const std::int32_t* r0 = acc_.data() + (t * kConv1OutFreq + g * kPoolFreq) * kConv1Maps;
      for (int ch = 0; ch < kConv1Maps; ++ch) {
        const std::int32_t m =
            std::max(r0[ch], std::max(r0[ch + kConv1Maps], r0[ch + 2 * kConv1Maps]));
        const std::size_t c = static_cast<std::size_t>(ch);
        out[ch] =
            quantize_value(static_cast<float>(m + conv1_.bias[c]) * conv1_.to_real[c], inv1, true);
      }
    }
  }
  detail::im2col_conv2(a1_.data(), cols2_.data());
  constexpr int p2 = kConv2OutTime * kConv2OutFreq;
  gemm(cols2_.data(), p2, conv2_, acc_.data());
  const float inv2 = 1.0f / scales_.conv2;
  for (int p = 0; p < p2; ++p) {
    for (int ch = 0; ch < kConv2Maps; ++ch) {
      const std::size_t c = static_cast<std::size_t>(ch);
      const std::int32_t v = acc_[static_cast<std::size_t>(p * kConv2Maps + ch)] + conv2_.bias[c];
      a2_[static_cast<std::size_t>(p * kConv2Maps + ch)] =
          quantize_value(static_cast<float>(v) * conv2_.to_real[c], inv2, true);
    }
  }
  auto fc = [this](const Layer& layer, const std::int16_t* in, std::int16_t* out, float out_scale,
                   bool relu) {
    gemm(in, 1, layer, acc_.data());
    const float inv = 1.0f / out_scale;
    for (std::size_t o = 0; o < static_cast<std::size_t>(layer.out); ++o) {
      out[o] =
          quantize_value(static_cast<float>(acc_[o] + layer.bias[o]) * layer.to_real[o], inv, relu);
    }
  };
  fc(linear_, a2_.data(), l_.data(), scales_.linear, false);
  fc(dense_, l_.data(), h_.data(), scales_.dense, true);
  gemm(h_.data(), 1, output_, acc_.data());
  for (std::size_t o = 0; o < static_cast<std::size_t>(kClasses); ++o) {
    probabilities[o] = static_cast<float>(acc_[o] + output_.bias[o]) * output_.to_real[o];
  }
  softmax(probabilities);
}

// The same arithmetic as run() with the AVX-512 kernels reading the convolutions' inputs in
// place (no im2col copies) and vectorised requantisation; both convolutions on bytes
// (vpdpbusd), the dense layers on int16 (vpdpwssd).
void Int8Inference::run_avx512(std::span<const float> input, std::span<float> probabilities) {
  std::uint8_t qin[kInputSize];  // quantised input + 128
  detail::quantize_input_u8_avx512(input.data(), kInputSize, 1.0f / scales_.input, qin);
  constexpr int p1 = kConv1OutTime * kConv1OutFreq;
  detail::gemm_avx512_packed(
      detail::RowsView<std::uint8_t>{qin, conv1_rows_.data(), p1, kConv1Freq, kBins}, conv1_bytes_,
      acc_.data());
  // Pooling: the 3 frequencies pooled together are consecutive rows (33 = 11 x 3 per frame).
  // The +128 shift adds the same 128 * sum(w) to all three, so taking it out after the max
  // (in the bias) is exact. After the ReLU every value is 0..127: conv2 takes them as bytes.
  detail::requantize_relu_avx512(acc_.data(), kConv1OutTime * kPooledFreq, kPoolFreq, kConv1Maps,
                                 conv1_shifted_bias_.data(), conv1_.to_real.data(),
                                 1.0f / scales_.conv1, a1_bytes_.data());
  constexpr int p2 = kConv2OutTime * kConv2OutFreq;
  detail::gemm_avx512_packed(
      detail::RowsView<std::uint8_t>{a1_bytes_.data(), conv2_rows_.data(), p2,
                                     kConv2Freq * kConv1Maps, kPooledFreq * kConv1Maps},
      conv2_bytes_, acc_.data());
  detail::requantize_avx512(acc_.data(), p2, 1, kConv2Maps, conv2_.bias.data(),
                            conv2_.to_real.data(), 1.0f / scales_.conv2, true, a2_.data());
  const std::int32_t first_row = 0;
  auto fc = [&](const Layer& layer, const std::int16_t* in, std::int16_t* out, float out_scale,
                bool relu) {
    detail::gemm_avx512_packed(
        detail::RowsView<std::int16_t>{in, &first_row, 1, layer.in, layer.in}, layer.packed,
        acc_.data());
    detail::requantize_avx512(acc_.data(), 1, 1, layer.out, layer.bias.data(), layer.to_real.data(),
                              1.0f / out_scale, relu, out);
  };
  fc(linear_, a2_.data(), l_.data(), scales_.linear, false);
  fc(dense_, l_.data(), h_.data(), scales_.dense, true);
  detail::gemm_avx512_packed(
      detail::RowsView<std::int16_t>{h_.data(), &first_row, 1, kDense, kDense}, output_.packed,
      acc_.data());
  for (std::size_t o = 0; o < static_cast<std::size_t>(kClasses); ++o) {
    probabilities[o] = static_cast<float>(acc_[o] + output_.bias[o]) * output_.to_real[o];
  }
  softmax(probabilities);
}

// The same arithmetic as run() with the AVX2 kernels reading the convolutions' inputs in
// place and vectorised requantisation: conv1 and the dense layers on int16 (vpmaddwd), conv2
// on bytes (vpmaddubsw; its input is 0..127, so the int16 pair sums cannot saturate).
void Int8Inference::run_avx2(std::span<const float> input, std::span<float> probabilities) {
  std::int16_t qin[kInputSize];
  detail::quantize_input_avx2(input.data(), kInputSize, 1.0f / scales_.input, qin);
  constexpr int p1 = kConv1OutTime * kConv1OutFreq;
  detail::gemm_avx2_packed(
      detail::RowsView<std::int16_t>{qin, conv1_rows_.data(), p1, kConv1Freq, kBins}, conv1_avx2_,
      acc_.data());
  detail::requantize_relu_avx2(acc_.data(), kConv1OutTime * kPooledFreq, kPoolFreq, kConv1Maps,
                               conv1_.bias.data(), conv1_.to_real.data(), 1.0f / scales_.conv1,
                               a1_bytes_.data());
  constexpr int p2 = kConv2OutTime * kConv2OutFreq;
  detail::gemm_avx2_packed(
      detail::RowsView<std::uint8_t>{a1_bytes_.data(), conv2_rows_.data(), p2,
                                     kConv2Freq * kConv1Maps, kPooledFreq * kConv1Maps},
      conv2_avx2_, acc_.data());
  detail::requantize_avx2(acc_.data(), p2, 1, kConv2Maps, conv2_.bias.data(), conv2_.to_real.data(),
                          1.0f / scales_.conv2, true, a2_.data());
  const std::int32_t first_row = 0;
  auto fc = [&](const Layer& layer, const std::int16_t* in, std::int16_t* out, float out_scale,
                bool relu) {
    detail::gemm_avx2_packed(detail::RowsView<std::int16_t>{in, &first_row, 1, layer.in, layer.in},
                             layer.packed256, acc_.data());
    detail::requantize_avx2(acc_.data(), 1, 1, layer.out, layer.bias.data(), layer.to_real.data(),
                            1.0f / out_scale, relu, out);
  };
  fc(linear_, a2_.data(), l_.data(), scales_.linear, false);
  fc(dense_, l_.data(), h_.data(), scales_.dense, true);
  detail::gemm_avx2_packed(detail::RowsView<std::int16_t>{h_.data(), &first_row, 1, kDense, kDense},
                           output_.packed256, acc_.data());
  for (std::size_t o = 0; o < static_cast<std::size_t>(kClasses); ++o) {
    probabilities[o] = static_cast<float>(acc_[o] + output_.bias[o]) * output_.to_real[o];
  }
  softmax(probabilities);
}

}  // namespace marvin::perception::kws
