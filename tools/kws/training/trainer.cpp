#include "kws/training/trainer.h"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <thread>

#include "perception/kws/im2col.h"
#include "perception/log_mel.h"

namespace marvin::perception::kws {

namespace {

using RowMatrix = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
using MatrixMap = Eigen::Map<RowMatrix>;
using ConstMatrixMap = Eigen::Map<const RowMatrix>;

constexpr int kP1 = kConv1OutTime * kConv1OutFreq;  // 429 conv1 positions
constexpr int kA1 = kConv1OutTime * kPooledFreq;    // 143 pooled positions
constexpr int kP2 = kConv2OutTime * kConv2OutFreq;  // 32 conv2 positions

ConstMatrixMap weights(const FloatLayer& l) {
  return ConstMatrixMap(l.weights.data(), l.out, l.in);
}
MatrixMap weights(FloatLayer& l) { return MatrixMap(l.weights.data(), l.out, l.in); }

void zero(FloatNetwork& n) {
  for (FloatLayer* l : n.layers()) {
    std::fill(l->weights.begin(), l->weights.end(), 0.0f);
    std::fill(l->bias.begin(), l->bias.end(), 0.0f);
  }
}

FloatNetwork zeros_like(const FloatNetwork& net) {
  FloatNetwork z = net;
  zero(z);
  return z;
}

void add_bias_rows(RowMatrix& m, const std::vector<float>& bias) {
  m.rowwise() +=
      Eigen::Map<const Eigen::RowVectorXf>(bias.data(), static_cast<Eigen::Index>(bias.size()));
}

void add_colsum(std::vector<float>& bias_grad, const RowMatrix& d) {
  Eigen::Map<Eigen::RowVectorXf>(bias_grad.data(), static_cast<Eigen::Index>(bias_grad.size())) +=
      d.colwise().sum();
}

// splitmix64: a well-mixed 64-bit value from a seed and an index.
std::uint64_t mix_seed(std::uint64_t seed, std::uint64_t index) {
  std::uint64_t z = seed + 0x9E3779B97F4A7C15ull * (index + 1);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

}  // namespace

void spec_mask(std::span<float> input, int freq_mask_bins, int time_mask_frames,
               std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  auto draw = [&rng](int max_width, int extent, auto&& clear) {
    if (max_width <= 0) return;
    const int width = std::uniform_int_distribution<int>(0, std::min(max_width, extent))(rng);
    const int first = std::uniform_int_distribution<int>(0, extent - width)(rng);
    for (int k = first; k < first + width; ++k) clear(k);
  };
  draw(freq_mask_bins, kBins, [&](int bin) {
    for (int t = 0; t < kInputFrames; ++t) input[static_cast<std::size_t>(t * kBins + bin)] = 0.0f;
  });
  draw(time_mask_frames, kInputFrames,
       [&](int t) { std::fill_n(input.begin() + t * kBins, kBins, 0.0f); });
}

void warp_frequency(std::span<float> input, float factor) {
  constexpr std::size_t n = kBins;
  // Bin centres in mel, as log_mel.cpp spaces them (n + 2 edges, centre i = edge i + 1).
  static const std::array<float, n> centre_mel = [] {
    const LogMelOptions o;
    const float low = hz_to_mel(o.low_hz), high = hz_to_mel(o.high_hz);
    std::array<float, n> c{};
    for (std::size_t i = 0; i < n; ++i) {
      c[i] = low + (high - low) * static_cast<float>(i + 1) / static_cast<float>(n + 1);
    }
    return c;
  }();
  const float step = centre_mel[1] - centre_mel[0];
  // Where each output bin reads from, as a fractional bin index (the same for every frame).
  std::array<std::size_t, n> lower{};
  std::array<float, n> frac{};
  for (std::size_t i = 0; i < n; ++i) {
    const float source_mel = hz_to_mel(mel_to_hz(centre_mel[i]) / factor);
    const float pos =
        std::clamp((source_mel - centre_mel[0]) / step, 0.0f, static_cast<float>(n - 1));
    lower[i] = std::min(static_cast<std::size_t>(pos), n - 2);
    frac[i] = pos - static_cast<float>(lower[i]);
  }
  std::array<float, n> frame{};
  for (int t = 0; t < kInputFrames; ++t) {
    float* row = input.data() + static_cast<std::ptrdiff_t>(t) * kBins;
    std::copy_n(row, n, frame.begin());
    for (std::size_t i = 0; i < n; ++i) {
      row[i] = frame[lower[i]] + frac[i] * (frame[lower[i] + 1] - frame[lower[i]]);
    }
  }
}

namespace {

bool augmenting(const TrainOptions& o) {
  return o.freq_mask_bins > 0 || o.time_mask_frames > 0 || o.freq_warp > 0.0f;
}

// One example's augmentation: a warp (its own stream, so turning warping on leaves the masks
// of a seed as they were), then the masks.
void augment_input(std::span<float> input, const TrainOptions& o, std::uint64_t seed) {
  if (o.freq_warp > 0.0f) {
    std::mt19937_64 rng(mix_seed(seed, 0x5741'5250ull));  // index "WARP" in ASCII
    const float span = std::log1p(o.freq_warp);
    warp_frequency(input, std::exp(std::uniform_real_distribution<float>(-span, span)(rng)));
  }
  spec_mask(input, o.freq_mask_bins, o.time_mask_frames, seed);
}

}  // namespace

// Scratch for one share of a batch.
struct Trainer::Worker {
  RowMatrix x1, z1, a1, x2, z2, a2, l, h, o;
  std::vector<float> augmented;  // one example's input after augment_input()
  std::vector<int> argmax;       // per a1 element: the z1 row the max came from
  FloatNetwork grad;
  double loss = 0.0;
  std::size_t correct = 0;

  // `first` is the position of idx[0] in the batch: with augmentation on, example k of the batch
  // is augmented with mix_seed(augment_seed, k) however the batch is split between workers.
  void run(const FloatNetwork& net, const TrainingSet& data, std::span<const std::size_t> idx,
           float inv_total, const TrainOptions& options, std::uint64_t augment_seed,
           std::size_t first) {
    const int b = static_cast<int>(idx.size());
    loss = 0.0;
    correct = 0;
    zero(grad);
    if (b == 0) return;
    x1.resize(b * kP1, kConv1In);
    for (int i = 0; i < b; ++i) {
      const std::span<const float> input = data.input(idx[static_cast<std::size_t>(i)]);
      const float* source = input.data();
      if (augmenting(options)) {
        augmented.assign(input.begin(), input.end());
        augment_input(augmented, options,
                      mix_seed(augment_seed, first + static_cast<std::size_t>(i)));
        source = augmented.data();
      }
      detail::im2col_conv1(source, x1.data() + static_cast<std::ptrdiff_t>(i) * kP1 * kConv1In);
    }
    z1.noalias() = x1 * weights(net.conv1).transpose();
    a1.resize(b * kA1, kConv1Maps);
    argmax.resize(static_cast<std::size_t>(b) * kA1 * kConv1Maps);
    for (int i = 0; i < b; ++i) {
      for (int t = 0; t < kConv1OutTime; ++t) {
        for (int g = 0; g < kPooledFreq; ++g) {
          const int row = i * kA1 + t * kPooledFreq + g;
          const int z0 = i * kP1 + t * kConv1OutFreq + g * kPoolFreq;
          for (int c = 0; c < kConv1Maps; ++c) {
            int best = z0;
            for (int k = 1; k < kPoolFreq; ++k) {
              if (z1(z0 + k, c) > z1(best, c)) best = z0 + k;
            }
            argmax[static_cast<std::size_t>(row) * kConv1Maps + c] = best;
            a1(row, c) = std::max(0.0f, z1(best, c) + net.conv1.bias[static_cast<std::size_t>(c)]);
          }
        }
      }
    }
    x2.resize(b * kP2, kConv2In);
    for (int i = 0; i < b; ++i) {
      detail::im2col_conv2(a1.data() + static_cast<std::ptrdiff_t>(i) * kA1 * kConv1Maps,
                           x2.data() + static_cast<std::ptrdiff_t>(i) * kP2 * kConv2In);
    }
    z2.noalias() = x2 * weights(net.conv2).transpose();
    add_bias_rows(z2, net.conv2.bias);
    a2 = z2.cwiseMax(0.0f);
    ConstMatrixMap flat(a2.data(), b, kFlat);
    l.noalias() = flat * weights(net.linear).transpose();
    add_bias_rows(l, net.linear.bias);
    h.noalias() = l * weights(net.dense).transpose();
    add_bias_rows(h, net.dense.bias);
    h = h.cwiseMax(0.0f);
    o.noalias() = h * weights(net.output).transpose();
    add_bias_rows(o, net.output.bias);

    // Softmax cross-entropy; o becomes dLoss/dlogits.
    for (int i = 0; i < b; ++i) {
      const int label = data.labels[idx[static_cast<std::size_t>(i)]];
      float m = o.row(i).maxCoeff();
      int pred = 0;
      for (int c = 1; c < kClasses; ++c) {
        if (o(i, c) > o(i, pred)) pred = c;
      }
      if (pred == label) ++correct;
      float sum = 0.0f;
      for (int c = 0; c < kClasses; ++c) {
        o(i, c) = std::exp(o(i, c) - m);
        sum += o(i, c);
      }
      for (int c = 0; c < kClasses; ++c) o(i, c) /= sum;
      loss -= std::log(std::max(o(i, label), 1e-12f));
      o(i, label) -= 1.0f;
    }
    o *= inv_total;
    RowMatrix& d_out = o;

    weights(grad.output).noalias() += d_out.transpose() * h;
    add_colsum(grad.output.bias, d_out);
    RowMatrix d_h = d_out * weights(net.output);
    d_h = d_h.cwiseProduct((h.array() > 0.0f).cast<float>().matrix());
    weights(grad.dense).noalias() += d_h.transpose() * l;
    add_colsum(grad.dense.bias, d_h);
    RowMatrix d_l = d_h * weights(net.dense);
    weights(grad.linear).noalias() += d_l.transpose() * flat;
    add_colsum(grad.linear.bias, d_l);
    RowMatrix d_flat = d_l * weights(net.linear);  // b x 2048
    MatrixMap d_z2(d_flat.data(), b * kP2, kConv2Maps);
    d_z2 = d_z2.cwiseProduct((a2.array() > 0.0f).cast<float>().matrix());
    weights(grad.conv2).noalias() += d_z2.transpose() * x2;
    Eigen::Map<Eigen::RowVectorXf>(grad.conv2.bias.data(), kConv2Maps) += d_z2.colwise().sum();
    RowMatrix d_x2 = d_z2 * weights(net.conv2);  // (b*32) x 2560
    // col2im into d_a1, then through the ReLU and the pooling to conv1's positions.
    RowMatrix d_a1 = RowMatrix::Zero(b * kA1, kConv1Maps);
    constexpr int span = kConv2Freq * kConv1Maps;
    for (int i = 0; i < b; ++i) {
      for (int t = 0; t < kConv2OutTime; ++t) {
        for (int f = 0; f < kConv2OutFreq; ++f) {
          const float* src =
              d_x2.data() + static_cast<std::ptrdiff_t>(i * kP2 + t * kConv2OutFreq + f) * kConv2In;
          for (int dt = 0; dt < kConv2Time; ++dt) {
            float* dst =
                d_a1.data() +
                static_cast<std::ptrdiff_t>(i * kA1 + (t + dt) * kPooledFreq + f) * kConv1Maps;
            const float* s = src + dt * span;
            for (int k = 0; k < span; ++k) dst[k] += s[k];
          }
        }
      }
    }
    RowMatrix d_z1 = RowMatrix::Zero(b * kP1, kConv1Maps);
    for (int row = 0; row < b * kA1; ++row) {
      for (int c = 0; c < kConv1Maps; ++c) {
        if (a1(row, c) > 0.0f) {
          const float g = d_a1(row, c);
          d_z1(argmax[static_cast<std::size_t>(row) * kConv1Maps + c], c) += g;
          grad.conv1.bias[static_cast<std::size_t>(c)] += g;
        }
      }
    }
    weights(grad.conv1).noalias() += d_z1.transpose() * x1;
  }
};

Trainer::Trainer(FloatNetwork& net, const TrainOptions& options)
    : net_(net), options_(options), m_(zeros_like(net)), v_(zeros_like(net)) {
  const int threads = std::max(1, options_.threads);
  for (int i = 0; i < threads; ++i) {
    workers_.push_back(std::make_unique<Worker>());
    workers_.back()->grad = zeros_like(net);
  }
}

Trainer::~Trainer() = default;

double Trainer::loss_and_gradient(const TrainingSet& data, std::span<const std::size_t> batch,
                                  FloatNetwork& gradient, std::size_t* correct) {
  const std::size_t n = workers_.size();
  const std::size_t per = (batch.size() + n - 1) / n;
  const float inv_total = 1.0f / static_cast<float>(std::max<std::size_t>(1, batch.size()));
  std::vector<std::thread> threads;
  for (std::size_t w = 1; w < n; ++w) {
    const std::size_t begin = std::min(batch.size(), w * per);
    const std::size_t end = std::min(batch.size(), begin + per);
    threads.emplace_back([&, w, begin, end] {
      workers_[w]->run(net_, data, batch.subspan(begin, end - begin), inv_total, options_,
                       augment_seed_, begin);
    });
  }
  workers_[0]->run(net_, data, batch.subspan(0, std::min(per, batch.size())), inv_total, options_,
                   augment_seed_, 0);
  for (std::thread& t : threads) t.join();
  gradient = workers_[0]->grad;
  double loss = workers_[0]->loss;
  std::size_t right = workers_[0]->correct;
  for (std::size_t w = 1; w < n; ++w) {
    auto dst = gradient.layers();
    auto src = workers_[w]->grad.layers();
    for (std::size_t k = 0; k < dst.size(); ++k) {
      for (std::size_t j = 0; j < dst[k]->weights.size(); ++j)
        dst[k]->weights[j] += src[k]->weights[j];
      for (std::size_t j = 0; j < dst[k]->bias.size(); ++j) dst[k]->bias[j] += src[k]->bias[j];
    }
    loss += workers_[w]->loss;
    right += workers_[w]->correct;
  }
  if (correct) *correct = right;
  return loss / static_cast<double>(std::max<std::size_t>(1, batch.size()));
}

void Trainer::adam_step(const FloatNetwork& gradient) {
  ++step_;
  const float b1 = options_.beta1, b2 = options_.beta2;
  const float c1 = 1.0f - std::pow(b1, static_cast<float>(step_));
  const float c2 = 1.0f - std::pow(b2, static_cast<float>(step_));
  const float lr = options_.learning_rate * std::sqrt(c2) / c1;
  auto p = net_.layers();
  auto g = gradient.layers();
  auto m = m_.layers();
  auto v = v_.layers();
  auto update = [&](std::vector<float>& param, const std::vector<float>& grad,
                    std::vector<float>& mom, std::vector<float>& vel, float decay) {
    for (std::size_t j = 0; j < param.size(); ++j) {
      const float gj = grad[j] + decay * param[j];
      mom[j] = b1 * mom[j] + (1.0f - b1) * gj;
      vel[j] = b2 * vel[j] + (1.0f - b2) * gj * gj;
      param[j] -= lr * mom[j] / (std::sqrt(vel[j]) + options_.epsilon);
    }
  };
  for (std::size_t k = 0; k < p.size(); ++k) {
    update(p[k]->weights, g[k]->weights, m[k]->weights, v[k]->weights, options_.weight_decay);
    update(p[k]->bias, g[k]->bias, m[k]->bias, v[k]->bias, 0.0f);
  }
}

EpochStats Trainer::train_epoch(
    const TrainingSet& data, std::mt19937_64& rng,
    const std::function<void(std::size_t, std::size_t, double, double)>& progress) {
  std::vector<std::size_t> order(data.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::shuffle(order.begin(), order.end(), rng);
  FloatNetwork gradient;
  double loss_sum = 0.0;
  std::size_t right = 0, done = 0;
  const std::size_t bs = static_cast<std::size_t>(std::max(1, options_.batch_size));
  for (std::size_t start = 0; start < order.size(); start += bs) {
    const std::size_t n = std::min(bs, order.size() - start);
    std::size_t correct = 0;
    if (augmenting(options_))
      augment_seed_ = rng();  // drawn only when on: runs without stay as before
    const double loss = loss_and_gradient(
        data, std::span<const std::size_t>(order).subspan(start, n), gradient, &correct);
    adam_step(gradient);
    loss_sum += loss * static_cast<double>(n);
    right += correct;
    done += n;
    if (progress) {
      progress(done, order.size(), loss_sum / static_cast<double>(done),
               static_cast<double>(right) / static_cast<double>(done));
    }
  }
  EpochStats s;
  if (done > 0) {
    s.loss = loss_sum / static_cast<double>(done);
    s.accuracy = static_cast<double>(right) / static_cast<double>(done);
  }
  return s;
}

double Accuracy::per_class(int cls) const {
  const auto& row = confusion[static_cast<std::size_t>(cls)];
  const int total = std::accumulate(row.begin(), row.end(), 0);
  return total > 0 ? static_cast<double>(row[static_cast<std::size_t>(cls)]) / total : 0.0;
}

namespace {

template <typename Inference>
Accuracy evaluate_with(Inference& inference, const TrainingSet& data) {
  Accuracy a;
  float probs[kClasses];
  std::size_t right = 0;
  for (std::size_t i = 0; i < data.size(); ++i) {
    inference.run(data.input(i), probs);
    const int pred = static_cast<int>(std::max_element(probs, probs + kClasses) - probs);
    const int label = data.labels[i];
    ++a.confusion[static_cast<std::size_t>(label)][static_cast<std::size_t>(pred)];
    if (pred == label) ++right;
  }
  a.overall = data.size() > 0 ? static_cast<double>(right) / static_cast<double>(data.size()) : 0.0;
  return a;
}

}  // namespace

Accuracy evaluate_float(const FloatNetwork& net, const TrainingSet& data) {
  FloatInference inference(net);
  return evaluate_with(inference, data);
}

Accuracy evaluate_int8(const QuantizedNetwork& net, const TrainingSet& data) {
  Int8Inference inference(net);
  return evaluate_with(inference, data);
}

ActivationScales calibrate(const FloatNetwork& net, const TrainingSet& data, double percentile,
                           std::size_t max_examples) {
  FloatInference inference(net);
  const std::size_t n = std::min(max_examples, data.size());
  if (n == 0) throw std::invalid_argument("kws calibrate: no examples");
  const std::size_t stride = data.size() / n;
  std::vector<float> r[5];
  float probs[kClasses];
  for (std::size_t i = 0; i < n; ++i) {
    inference.run(data.input(i * stride), probs);
    const ActivationScales& s = inference.last_ranges();
    r[0].push_back(s.input);
    r[1].push_back(s.conv1);
    r[2].push_back(s.conv2);
    r[3].push_back(s.linear);
    r[4].push_back(s.dense);
  }
  float out[5];
  for (int k = 0; k < 5; ++k) {
    auto& v = r[k];
    std::sort(v.begin(), v.end());
    const std::size_t at = std::min(
        v.size() - 1, static_cast<std::size_t>(percentile * static_cast<double>(v.size())));
    out[k] = std::max(v[at], 1e-6f) / 127.0f;
  }
  return ActivationScales{out[0], out[1], out[2], out[3], out[4]};
}

}  // namespace marvin::perception::kws
