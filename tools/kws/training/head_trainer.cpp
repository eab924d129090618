#include "kws/training/head_trainer.h"

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <fstream>
#include <numeric>
#include <random>
#include <stdexcept>

#include "perception/kws/model_file.h"

namespace marvin::perception::kws {
namespace {

using HeadMatrix = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// Adam state of one parameter block.
struct AdamBlock {
  std::vector<float> m, v;
  explicit AdamBlock(std::size_t n) : m(n, 0.0f), v(n, 0.0f) {}
  void step(std::vector<float>& w, const std::vector<float>& g, float lr, float decay, int t) {
    constexpr float b1 = 0.9f, b2 = 0.999f, eps = 1e-8f;
    const float c1 = 1.0f - std::pow(b1, static_cast<float>(t));
    const float c2 = 1.0f - std::pow(b2, static_cast<float>(t));
    for (std::size_t k = 0; k < w.size(); ++k) {
      const float grad = g[k] + decay * w[k];
      m[k] = b1 * m[k] + (1.0f - b1) * grad;
      v[k] = b2 * v[k] + (1.0f - b2) * grad * grad;
      w[k] -= lr * (m[k] / c1) / (std::sqrt(v[k] / c2) + eps);
    }
  }
};

}  // namespace

void HeadSet::add(std::span<const float> input, float label) {
  if (input.size() != static_cast<std::size_t>(kHeadInputs)) {
    throw std::invalid_argument("HeadSet::add: " + std::to_string(input.size()) +
                                " numbers, expected 16 x 96 = 1536");
  }
  inputs.insert(inputs.end(), input.begin(), input.end());
  labels.push_back(label);
}

void HeadSet::append(const HeadSet& other) {
  inputs.insert(inputs.end(), other.inputs.begin(), other.inputs.end());
  labels.insert(labels.end(), other.labels.begin(), other.labels.end());
}

EmbeddingHead train_head(const HeadSet& train, const HeadTrainOptions& options) {
  if (train.size() == 0) throw std::invalid_argument("train_head: no examples");
  std::mt19937_64 rng(options.seed);
  EmbeddingHead head;
  head.resize(options.hidden);
  const int h = options.hidden;
  auto init = [&](std::vector<float>& w, int fan_in, float input_std) {
    std::normal_distribution<float> d(0.0f,
                                      std::sqrt(2.0f / static_cast<float>(fan_in)) / input_std);
    for (float& x : w) x = d(rng);
  };
  // He initialisation scaled by the inputs' spread (speech embeddings have a standard
  // deviation around 15), so the first layer starts at unit scale without a normalisation
  // layer in the file.
  double sum = 0.0, sum2 = 0.0;
  for (const float v : train.inputs) {
    sum += v;
    sum2 += static_cast<double>(v) * v;
  }
  const double count = static_cast<double>(train.inputs.size());
  const auto input_std = static_cast<float>(
      std::max(1e-3, std::sqrt(std::max(0.0, sum2 / count - (sum / count) * (sum / count)))));
  init(head.w1, kHeadInputs, input_std);
  init(head.w2, h, 1.0f);
  init(head.w3, h, 1.0f);
  AdamBlock a_w1(head.w1.size()), a_b1(head.b1.size()), a_w2(head.w2.size()), a_b2(head.b2.size()),
      a_w3(head.w3.size());
  std::vector<float> b3v{0.0f};
  AdamBlock a_b3(1);
  std::vector<float> g_w1(head.w1.size()), g_b1(head.b1.size()), g_w2(head.w2.size()),
      g_b2(head.b2.size()), g_w3(head.w3.size()), g_b3(1);

  std::vector<std::size_t> order(train.size());
  std::iota(order.begin(), order.end(), 0);
  const auto batch = static_cast<std::size_t>(std::max(1, options.batch));
  const std::size_t batches = (order.size() + batch - 1) / batch;
  int t = 0;
  HeadMatrix x, z1, a1, z2, a2, d2, d1;
  for (int epoch = 0; epoch < options.epochs; ++epoch) {
    std::shuffle(order.begin(), order.end(), rng);
    // Cosine decay to 5 % of the rate, as the CNN trainer does.
    const float lr = options.learning_rate *
                     (0.05f + 0.95f * 0.5f *
                                  (1.0f + std::cos(3.14159265f * static_cast<float>(epoch) /
                                                   static_cast<float>(options.epochs))));
    const float negative_weight = options.epochs > 1
                                      ? 1.0f + (options.final_negative_weight - 1.0f) *
                                                   static_cast<float>(epoch) /
                                                   static_cast<float>(options.epochs - 1)
                                      : options.final_negative_weight;
    double loss_sum = 0.0;
    std::size_t seen = 0;
    for (std::size_t bi = 0; bi < batches; ++bi) {
      const std::size_t first = bi * batch;
      const auto n = static_cast<Eigen::Index>(std::min(batch, order.size() - first));
      x.resize(kHeadInputs, n);
      for (Eigen::Index c = 0; c < n; ++c) {
        const float* src =
            train.inputs.data() + order[first + static_cast<std::size_t>(c)] * kHeadInputs;
        for (int r = 0; r < kHeadInputs; ++r) x(r, c) = src[r];
      }
      const Eigen::Map<const HeadMatrix> w1(head.w1.data(), h, kHeadInputs);
      const Eigen::Map<const HeadMatrix> w2(head.w2.data(), h, h);
      const Eigen::Map<const Eigen::RowVectorXf> w3(head.w3.data(), h);
      const Eigen::Map<const Eigen::VectorXf> b1(head.b1.data(), h), b2(head.b2.data(), h);
      z1.noalias() = w1 * x;
      z1.colwise() += b1;
      a1 = z1.cwiseMax(0.0f);
      z2.noalias() = w2 * a1;
      z2.colwise() += b2;
      a2 = z2.cwiseMax(0.0f);
      const Eigen::RowVectorXf z3 = (w3 * a2).array() + head.b3;
      // dL/dz3 for weighted cross-entropy on sigmoid(z3), averaged over the batch.
      Eigen::RowVectorXf d3(n);
      float weight_sum = 0.0f;
      for (Eigen::Index c = 0; c < n; ++c) {
        const float y = train.labels[order[first + static_cast<std::size_t>(c)]];
        const float w = y > 0.5f ? options.positive_weight : negative_weight;
        const float p = 1.0f / (1.0f + std::exp(-z3(c)));
        d3(c) = w * (p - y);
        weight_sum += w;
        const float pc = std::clamp(p, 1e-7f, 1.0f - 1e-7f);
        loss_sum += static_cast<double>(-w * (y * std::log(pc) + (1.0f - y) * std::log(1.0f - pc)));
      }
      d3 /= weight_sum;
      seen += static_cast<std::size_t>(n);
      Eigen::Map<Eigen::RowVectorXf>(g_w3.data(), h) = d3 * a2.transpose();
      g_b3[0] = d3.sum();
      d2 = (w3.transpose() * d3).cwiseProduct((z2.array() > 0.0f).cast<float>().matrix());
      Eigen::Map<HeadMatrix>(g_w2.data(), h, h).noalias() = d2 * a1.transpose();
      Eigen::Map<Eigen::VectorXf>(g_b2.data(), h) = d2.rowwise().sum();
      d1 = (w2.transpose() * d2).cwiseProduct((z1.array() > 0.0f).cast<float>().matrix());
      Eigen::Map<HeadMatrix>(g_w1.data(), h, kHeadInputs).noalias() = d1 * x.transpose();
      Eigen::Map<Eigen::VectorXf>(g_b1.data(), h) = d1.rowwise().sum();
      ++t;
      a_w1.step(head.w1, g_w1, lr, options.weight_decay, t);
      a_b1.step(head.b1, g_b1, lr, 0.0f, t);
      a_w2.step(head.w2, g_w2, lr, options.weight_decay, t);
      a_b2.step(head.b2, g_b2, lr, 0.0f, t);
      a_w3.step(head.w3, g_w3, lr, options.weight_decay, t);
      b3v[0] = head.b3;
      a_b3.step(b3v, g_b3, lr, 0.0f, t);
      head.b3 = b3v[0];
      if (options.progress) {
        options.progress(epoch, bi + 1, batches, loss_sum / static_cast<double>(seen));
      }
    }
  }
  return head;
}

EmbeddingHead merge_heads(const std::vector<EmbeddingHead>& members) {
  if (members.empty()) throw std::invalid_argument("merge_heads: no heads to merge");
  std::size_t total = 0;
  for (const EmbeddingHead& m : members) {
    if (m.keyword != members.front().keyword) {
      throw std::invalid_argument("merge_heads: heads for \"" + members.front().keyword +
                                  "\" and \"" + m.keyword + "\" cannot be merged");
    }
    total += static_cast<std::size_t>(m.hidden);
  }
  if (total > 1024) {
    throw std::invalid_argument("merge_heads: " + std::to_string(total) +
                                " hidden units together, a head holds at most 1024");
  }
  EmbeddingHead out = members.front();
  out.resize(static_cast<int>(total));
  const float share = 1.0f / static_cast<float>(members.size());
  out.b3 = 0.0f;
  std::size_t at = 0;  // the member's first unit in the merged layers
  for (const EmbeddingHead& m : members) {
    const auto h = static_cast<std::size_t>(m.hidden);
    std::copy(m.w1.begin(), m.w1.end(),
              out.w1.begin() + static_cast<std::ptrdiff_t>(at * kHeadInputs));
    for (std::size_t o = 0; o < h; ++o) {
      out.b1[at + o] = m.b1[o];
      out.b2[at + o] = m.b2[o];
      out.w3[at + o] = m.w3[o] * share;
      for (std::size_t i = 0; i < h; ++i) out.w2[(at + o) * total + at + i] = m.w2[o * h + i];
    }
    out.b3 += m.b3 * share;
    at += h;
  }
  return out;
}

HeadAccuracy head_accuracy(const EmbeddingHead& head, const HeadSet& set, float threshold) {
  std::size_t pos = 0, pos_ok = 0, neg = 0, neg_ok = 0;
  for (std::size_t k = 0; k < set.size(); ++k) {
    const float s =
        head.score(std::span<const float>(set.inputs).subspan(k * kHeadInputs, kHeadInputs));
    if (set.labels[k] > 0.5f) {
      ++pos;
      pos_ok += s >= threshold ? 1 : 0;
    } else {
      ++neg;
      neg_ok += s < threshold ? 1 : 0;
    }
  }
  return {pos ? static_cast<double>(pos_ok) / static_cast<double>(pos) : 0.0,
          neg ? static_cast<double>(neg_ok) / static_cast<double>(neg) : 0.0};
}

}  // namespace marvin::perception::kws

namespace marvin::perception::kws {
namespace {

constexpr char kFeatureMagic[8] = {'M', 'K', 'W', 'S', 'F', 'E', 'A', 'T'};
constexpr std::uint32_t kFeatureVersion = 1;

}  // namespace

void save_head_set(const std::filesystem::path& path, const HeadSet& set) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) throw ModelFileError(path.string() + ": cannot open for writing");
  const std::uint32_t version = kFeatureVersion, inputs = kHeadInputs;
  const std::uint64_t n = set.size();
  out.write(kFeatureMagic, sizeof kFeatureMagic);
  out.write(reinterpret_cast<const char*>(&version), sizeof version);
  out.write(reinterpret_cast<const char*>(&inputs), sizeof inputs);
  out.write(reinterpret_cast<const char*>(&n), sizeof n);
  out.write(reinterpret_cast<const char*>(set.labels.data()),
            static_cast<std::streamsize>(n * sizeof(float)));
  out.write(reinterpret_cast<const char*>(set.inputs.data()),
            static_cast<std::streamsize>(set.inputs.size() * sizeof(float)));
  if (!out) throw ModelFileError(path.string() + ": write failed");
}

HeadSet load_head_set(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ModelFileError(path.string() + ": cannot open feature file");
  char magic[8] = {};
  std::uint32_t version = 0, inputs = 0;
  std::uint64_t n = 0;
  in.read(magic, sizeof magic);
  if (!in || !std::equal(magic, magic + 8, kFeatureMagic)) {
    throw ModelFileError(path.string() + ": bytes 0..7: expected \"MKWSFEAT\" (a feature file)");
  }
  in.read(reinterpret_cast<char*>(&version), sizeof version);
  in.read(reinterpret_cast<char*>(&inputs), sizeof inputs);
  in.read(reinterpret_cast<char*>(&n), sizeof n);
  if (!in) throw ModelFileError(path.string() + ": truncated header (24 bytes expected)");
  if (version != kFeatureVersion) {
    throw ModelFileError(path.string() + ": byte 8: version " + std::to_string(version) +
                         ", expected " + std::to_string(kFeatureVersion));
  }
  if (inputs != static_cast<std::uint32_t>(kHeadInputs)) {
    throw ModelFileError(path.string() + ": byte 12: " + std::to_string(inputs) +
                         " inputs per example, expected " + std::to_string(kHeadInputs));
  }
  const std::uint64_t expected = 24 + n * (1 + kHeadInputs) * sizeof(float);
  const std::uint64_t size = std::filesystem::file_size(path);
  if (size != expected) {
    throw ModelFileError(path.string() + ": " + std::to_string(size) + " bytes, expected " +
                         std::to_string(expected) + " for " + std::to_string(n) + " examples");
  }
  HeadSet set;
  set.labels.resize(n);
  set.inputs.resize(n * kHeadInputs);
  in.read(reinterpret_cast<char*>(set.labels.data()),
          static_cast<std::streamsize>(n * sizeof(float)));
  in.read(reinterpret_cast<char*>(set.inputs.data()),
          static_cast<std::streamsize>(set.inputs.size() * sizeof(float)));
  if (!in) throw ModelFileError(path.string() + ": truncated");
  return set;
}

}  // namespace marvin::perception::kws
