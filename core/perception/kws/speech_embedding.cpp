#include "perception/kws/speech_embedding.h"

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <stdexcept>
#include <string>

#include "perception/kws/onnx_file.h"

#ifndef MARVIN_KWS_EMBEDDING_DIR
#define MARVIN_KWS_EMBEDDING_DIR ".cache/kws"
#endif

namespace marvin::perception::kws {
namespace {

using RowMatrix = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

[[noreturn]] void graph_error(const OnnxGraph& g, std::size_t node, const std::string& message) {
  throw OnnxError(g.file.string() + ": node " + std::to_string(node) + " (" +
                  (node < g.nodes.size() ? g.nodes[node].op_type : std::string("end")) +
                  "): " + message);
}

std::string dims_text(const std::vector<std::int64_t>& dims) {
  std::string s = "[";
  for (std::size_t k = 0; k < dims.size(); ++k) s += (k ? "," : "") + std::to_string(dims[k]);
  return s + "]";
}

// The one scalar of a constant input (a Constant node's output or an initializer).
float scalar_input(const OnnxGraph& g, std::size_t node, std::size_t input) {
  const OnnxNode& n = g.nodes[node];
  if (n.inputs.size() <= input) graph_error(g, node, "has no input " + std::to_string(input));
  const OnnxTensor& t = g.constant(n.inputs[input]);
  if (t.floats.size() != 1) graph_error(g, node, "input '" + n.inputs[input] + "' is not one float");
  return t.floats[0];
}

}  // namespace

std::filesystem::path embedding_model_dir() {
  if (const char* env = std::getenv("MARVIN_KWS_EMBEDDING_DIR"); env != nullptr && *env != '\0') {
    return env;
  }
  return MARVIN_KWS_EMBEDDING_DIR;
}

void require_embedding_models(const std::filesystem::path& dir) {
  for (const char* name : {"melspectrogram.onnx", "embedding_model.onnx"}) {
    const std::filesystem::path file = dir / name;
    if (!std::filesystem::exists(file)) {
      throw std::runtime_error(file.string() +
                               ": missing (the embedding wake word's pretrained model; run "
                               "scripts/setup, which fetches it, or set MARVIN_KWS_EMBEDDING_DIR)");
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Mel front end

struct MelFrontEnd::Weights {
  int window = 512;
  int hop = 160;
  int bins = 257;
  RowMatrix dft;      // window x (2 * bins): real filters, then imaginary
  RowMatrix mel;      // bins x 32
  float floor = 1e-10f;
  float ceiling = std::numeric_limits<float>::infinity();
  float multiplier = 10.0f;
  float divisor = 2.3025851f;
  float offset = 0.0f;
  float top_db = 80.0f;
  float out_ceiling = std::numeric_limits<float>::infinity();
};

MelFrontEnd::MelFrontEnd(const std::filesystem::path& onnx_file) : w_(std::make_unique<Weights>()) {
  const OnnxGraph g = read_onnx(onnx_file);
  // The operators melspectrogram.onnx is made of, in order (Constant nodes left out).
  static const std::vector<std::string> expected = {
      "Unsqueeze", "Conv", "Conv", "Unsqueeze", "Transpose", "Unsqueeze", "Transpose", "Pow",
      "Pow", "Add", "MatMul", "Clip", "Log", "Mul", "Div", "Sub", "ReduceMax", "Sub", "Cast",
      "Clip"};
  std::vector<std::size_t> at;
  for (std::size_t k = 0; k < g.nodes.size(); ++k) {
    if (g.nodes[k].op_type != "Constant") at.push_back(k);
  }
  for (std::size_t k = 0; k < std::max(at.size(), expected.size()); ++k) {
    if (k >= at.size() || k >= expected.size() || g.nodes[at[k]].op_type != expected[k]) {
      graph_error(g, k < at.size() ? at[k] : g.nodes.size(),
                  "expected operator " + (k < expected.size() ? expected[k] : "none") +
                      " (the graph is not openWakeWord's melspectrogram)");
    }
  }
  Weights& w = *w_;
  const OnnxNode& real = g.nodes[at[1]];
  const OnnxNode& imag = g.nodes[at[2]];
  const OnnxTensor& wr = g.constant(real.inputs.at(1));
  const OnnxTensor& wi = g.constant(imag.inputs.at(1));
  if (wr.dims.size() != 3 || wr.dims[1] != 1 || wr.dims != wi.dims) {
    graph_error(g, at[1], "DFT filters are " + dims_text(wr.dims) + " and " + dims_text(wi.dims) +
                              ", expected [bins,1,window] both");
  }
  w.bins = static_cast<int>(wr.dims[0]);
  w.window = static_cast<int>(wr.dims[2]);
  const auto strides = real.ints("strides");
  if (strides.size() != 1 || real.ints("pads", {0, 0}) != std::vector<std::int64_t>{0, 0}) {
    graph_error(g, at[1], "expected one stride and no padding");
  }
  w.hop = static_cast<int>(strides[0]);
  w.dft.resize(w.window, 2 * w.bins);
  for (int b = 0; b < w.bins; ++b) {
    for (int n = 0; n < w.window; ++n) {
      w.dft(n, b) = wr.floats[static_cast<std::size_t>(b * w.window + n)];
      w.dft(n, w.bins + b) = wi.floats[static_cast<std::size_t>(b * w.window + n)];
    }
  }
  const OnnxTensor& mel = g.constant(g.nodes[at[10]].inputs.at(1));
  if (mel.dims != std::vector<std::int64_t>{w.bins, kMelBins}) {
    graph_error(g, at[10], "mel matrix is " + dims_text(mel.dims) + ", expected [" +
                               std::to_string(w.bins) + "," + std::to_string(kMelBins) + "]");
  }
  w.mel = Eigen::Map<const RowMatrix>(mel.floats.data(), w.bins, kMelBins);
  w.floor = scalar_input(g, at[11], 1);
  w.ceiling = scalar_input(g, at[11], 2);
  w.multiplier = scalar_input(g, at[13], 1);
  w.divisor = scalar_input(g, at[14], 1);
  w.offset = scalar_input(g, at[15], 1);
  w.top_db = scalar_input(g, at[17], 1);
  w.out_ceiling = scalar_input(g, at[19], 2);
  if (w.hop != 160 || w.window != 512) {
    graph_error(g, at[1], "window " + std::to_string(w.window) + " hop " + std::to_string(w.hop) +
                              ", expected 512 and 160 (openWakeWord's 1280-sample hops)");
  }
}

MelFrontEnd::~MelFrontEnd() = default;
MelFrontEnd::MelFrontEnd(MelFrontEnd&&) noexcept = default;

std::size_t MelFrontEnd::frames_for(std::size_t samples) {
  return samples < 512 ? 0 : (samples - 512) / 160 + 1;
}

std::vector<float> MelFrontEnd::compute(std::span<const float> samples) const {
  const Weights& w = *w_;
  const auto window = static_cast<std::size_t>(w.window);
  const std::size_t frames =
      samples.size() < window ? 0 : (samples.size() - window) / static_cast<std::size_t>(w.hop) + 1;
  std::vector<float> out(frames * kMelBins);
  if (frames == 0) return out;
  RowMatrix x(static_cast<Eigen::Index>(frames), w.window);
  for (std::size_t f = 0; f < frames; ++f) {
    std::copy_n(samples.data() + f * static_cast<std::size_t>(w.hop), window,
                x.data() + f * window);
  }
  const RowMatrix spectrum = x * w.dft;
  const RowMatrix power = spectrum.leftCols(w.bins).array().square() +
                          spectrum.rightCols(w.bins).array().square();
  const RowMatrix mel = power * w.mel;
  float top = -std::numeric_limits<float>::infinity();
  for (Eigen::Index k = 0; k < mel.size(); ++k) {
    const float clipped = std::min(std::max(mel.data()[k], w.floor), w.ceiling);
    // Same order of float operations as the graph: log, * 10, / ln 10, - 0.
    const float db = std::log(clipped) * w.multiplier / w.divisor - w.offset;
    out[static_cast<std::size_t>(k)] = db;
    top = std::max(top, db);
  }
  const float lowest = top - w.top_db;
  for (float& v : out) v = std::min(std::max(v, lowest), w.out_ceiling);
  return out;
}

// ---------------------------------------------------------------------------------------------
// Speech embedding

namespace {

struct Layer {
  enum class Kind { conv, leaky_relu, max_constant, max_pool } kind = Kind::conv;
  // conv
  int out = 0, in = 0, kh = 0, kw = 0, pad_top = 0, pad_left = 0, pad_bottom = 0, pad_right = 0;
  RowMatrix weights;              // out x (in * kh * kw)
  Eigen::VectorXf bias;           // out (zeros when the graph has none)
  // leaky_relu: alpha; max_constant: the constant
  float value = 0.0f;
  // max_pool
  int pool_h = 0, pool_w = 0, stride_h = 0, stride_w = 0;
};

struct Shape {
  int c = 0, h = 0, w = 0;
};

}  // namespace

struct SpeechEmbedding::Layers {
  std::vector<Layer> layers;
  std::vector<Shape> shapes;  // each layer's output
  std::int64_t macs = 0;
  // Every convolution is unpadded in time and every pooling's time kernel equals its stride,
  // so a window moved by 8 frames shares all but its last rows with the one before.
  bool incremental = true;
};

SpeechEmbedding::SpeechEmbedding(const std::filesystem::path& onnx_file)
    : layers_(std::make_unique<Layers>()) {
  const OnnxGraph g = read_onnx(onnx_file);
  Shape shape{};
  std::string current;  // the chain's current tensor
  for (std::size_t k = 0; k < g.nodes.size(); ++k) {
    const OnnxNode& n = g.nodes[k];
    if (n.outputs.size() != 1) graph_error(g, k, "expected one output");
    if (k > 0 && (n.inputs.empty() || n.inputs[0] != current)) {
      graph_error(g, k, "does not continue the chain from '" + current + "'");
    }
    current = n.outputs[0];
    if (n.op_type == "Reshape") {
      const OnnxTensor& to = g.constant(n.inputs.at(1));
      if (k == 0) {
        if (to.ints != std::vector<std::int64_t>{-1, 1, kEmbeddingFrames, kMelBins}) {
          graph_error(g, k, "reshapes the input to " + dims_text(to.ints) + ", expected [-1,1,76,32]");
        }
        shape = {1, kEmbeddingFrames, kMelBins};
      } else if (k + 1 == g.nodes.size()) {
        if (shape.c != kEmbeddingSize || shape.h != 1 || shape.w != 1) {
          graph_error(g, k, "the network ends in " + std::to_string(shape.c) + "x" +
                                std::to_string(shape.h) + "x" + std::to_string(shape.w) +
                                ", expected 96x1x1");
        }
      } else {
        graph_error(g, k, "a Reshape in the middle of the network");
      }
      continue;
    }
    if (k == 0) graph_error(g, k, "expected the input Reshape first");
    Layer layer;
    if (n.op_type == "Conv") {
      const OnnxTensor& wt = g.constant(n.inputs.at(1));
      if (wt.dims.size() != 4 || wt.dims[1] != shape.c) {
        graph_error(g, k, "weights " + dims_text(wt.dims) + " for an input of " +
                              std::to_string(shape.c) + " channels");
      }
      if (n.ints("strides", {1, 1}) != std::vector<std::int64_t>{1, 1} ||
          n.ints("dilations", {1, 1}) != std::vector<std::int64_t>{1, 1} ||
          (n.attributes.count("group") && n.attributes.at("group").i != 1)) {
        graph_error(g, k, "expected strides 1, dilations 1 and one group");
      }
      const auto pads = n.ints("pads", {0, 0, 0, 0});
      if (pads.size() != 4) graph_error(g, k, "pads " + dims_text(pads) + ", expected 4 values");
      layer.kind = Layer::Kind::conv;
      layer.out = static_cast<int>(wt.dims[0]);
      layer.in = static_cast<int>(wt.dims[1]);
      layer.kh = static_cast<int>(wt.dims[2]);
      layer.kw = static_cast<int>(wt.dims[3]);
      layer.pad_top = static_cast<int>(pads[0]);
      layer.pad_left = static_cast<int>(pads[1]);
      layer.pad_bottom = static_cast<int>(pads[2]);
      layer.pad_right = static_cast<int>(pads[3]);
      layer.weights = Eigen::Map<const RowMatrix>(wt.floats.data(), layer.out,
                                                  layer.in * layer.kh * layer.kw);
      layer.bias = Eigen::VectorXf::Zero(layer.out);
      if (n.inputs.size() > 2) {
        const OnnxTensor& b = g.constant(n.inputs[2]);
        if (b.floats.size() != static_cast<std::size_t>(layer.out)) graph_error(g, k, "bias size");
        layer.bias = Eigen::Map<const Eigen::VectorXf>(b.floats.data(), layer.out);
      }
      shape = {layer.out, shape.h + layer.pad_top + layer.pad_bottom - layer.kh + 1,
               shape.w + layer.pad_left + layer.pad_right - layer.kw + 1};
      if (shape.h < 1 || shape.w < 1) graph_error(g, k, "the feature map became empty");
      layers_->macs += static_cast<std::int64_t>(layer.weights.size()) * shape.h * shape.w;
    } else if (n.op_type == "LeakyRelu") {
      layer.kind = Layer::Kind::leaky_relu;
      layer.value = n.attributes.count("alpha") ? n.attributes.at("alpha").f : 0.01f;
    } else if (n.op_type == "Max") {
      if (n.inputs.size() != 2) graph_error(g, k, "expected two inputs");
      const OnnxTensor& c = g.constant(n.inputs[1]);
      if (c.floats.size() != 1) graph_error(g, k, "expected max with one constant");
      layer.kind = Layer::Kind::max_constant;
      layer.value = c.floats[0];
    } else if (n.op_type == "MaxPool") {
      const auto kernel = n.ints("kernel_shape");
      const auto strides = n.ints("strides", {1, 1});
      if (kernel.size() != 2 || strides.size() != 2 ||
          n.ints("pads", {0, 0, 0, 0}) != std::vector<std::int64_t>{0, 0, 0, 0}) {
        graph_error(g, k, "expected a 2-D kernel, 2 strides and no padding");
      }
      layer.kind = Layer::Kind::max_pool;
      layer.pool_h = static_cast<int>(kernel[0]);
      layer.pool_w = static_cast<int>(kernel[1]);
      layer.stride_h = static_cast<int>(strides[0]);
      layer.stride_w = static_cast<int>(strides[1]);
      shape = {shape.c, (shape.h - layer.pool_h) / layer.stride_h + 1,
               (shape.w - layer.pool_w) / layer.stride_w + 1};
    } else {
      graph_error(g, k, "operator not supported by Marvin's embedding runner");
    }
    if (layer.kind == Layer::Kind::conv && (layer.pad_top != 0 || layer.pad_bottom != 0)) {
      layers_->incremental = false;
    }
    if (layer.kind == Layer::Kind::max_pool && layer.pool_h != layer.stride_h) {
      layers_->incremental = false;
    }
    layers_->layers.push_back(std::move(layer));
    layers_->shapes.push_back(shape);
  }
  if (g.nodes.back().op_type != "Reshape") graph_error(g, g.nodes.size() - 1, "expected the output Reshape last");
}

SpeechEmbedding::~SpeechEmbedding() = default;
SpeechEmbedding::SpeechEmbedding(SpeechEmbedding&&) noexcept = default;

std::int64_t SpeechEmbedding::macs() const { return layers_->macs; }

namespace {

// One layer's output rows [row_begin, shape.h) from its full input `x` (shape `in`), written
// into `out` (shape `shape`), which may already hold the other rows.
void run_rows(const Layer& layer, const std::vector<float>& x, const Shape& in, int row_begin,
              std::vector<float>& out, const Shape& shape, std::vector<float>& col,
              std::vector<float>& y) {
  const int rows = shape.h - row_begin;
  switch (layer.kind) {
    case Layer::Kind::conv: {
      const int ho = shape.h, wo = shape.w;
      const int k_rows = layer.in * layer.kh * layer.kw;
      const std::size_t n = static_cast<std::size_t>(rows * wo);
      col.assign(static_cast<std::size_t>(k_rows) * n, 0.0f);
      for (int c = 0; c < layer.in; ++c) {
        for (int i = 0; i < layer.kh; ++i) {
          for (int j = 0; j < layer.kw; ++j) {
            float* dst = col.data() + static_cast<std::size_t>((c * layer.kh + i) * layer.kw + j) * n;
            for (int oy = row_begin; oy < ho; ++oy) {
              const int iy = oy + i - layer.pad_top;
              if (iy < 0 || iy >= in.h) continue;
              const float* src = x.data() + static_cast<std::size_t>((c * in.h + iy) * in.w);
              float* d = dst + static_cast<std::size_t>((oy - row_begin) * wo);
              for (int ox = 0; ox < wo; ++ox) {
                const int ix = ox + j - layer.pad_left;
                if (ix >= 0 && ix < in.w) d[ox] = src[ix];
              }
            }
          }
        }
      }
      y.resize(static_cast<std::size_t>(layer.out) * n);
      Eigen::Map<RowMatrix> result(y.data(), layer.out, static_cast<Eigen::Index>(n));
      result.noalias() = layer.weights * Eigen::Map<const RowMatrix>(col.data(), k_rows,
                                                                      static_cast<Eigen::Index>(n));
      result.colwise() += layer.bias;
      for (int o = 0; o < layer.out; ++o) {
        std::copy_n(y.data() + static_cast<std::size_t>(o) * n, n,
                    out.data() + static_cast<std::size_t>((o * ho + row_begin) * wo));
      }
      break;
    }
    case Layer::Kind::leaky_relu:
    case Layer::Kind::max_constant:
      for (int c = 0; c < shape.c; ++c) {
        float* p = out.data() + static_cast<std::size_t>((c * shape.h + row_begin) * shape.w);
        float* e = p + static_cast<std::size_t>(rows * shape.w);
        if (layer.kind == Layer::Kind::leaky_relu) {
          for (; p != e; ++p) *p = *p >= 0.0f ? *p : *p * layer.value;
        } else {
          for (; p != e; ++p) *p = std::max(*p, layer.value);
        }
      }
      break;
    case Layer::Kind::max_pool:
      for (int c = 0; c < shape.c; ++c) {
        for (int oy = row_begin; oy < shape.h; ++oy) {
          for (int ox = 0; ox < shape.w; ++ox) {
            float best = -std::numeric_limits<float>::infinity();
            for (int i = 0; i < layer.pool_h; ++i) {
              for (int j = 0; j < layer.pool_w; ++j) {
                best = std::max(best, x[static_cast<std::size_t>(
                                          (c * in.h + oy * layer.stride_h + i) * in.w +
                                          ox * layer.stride_w + j)]);
              }
            }
            out[static_cast<std::size_t>((c * shape.h + oy) * shape.w + ox)] = best;
          }
        }
      }
      break;
  }
}

}  // namespace

Embedding SpeechEmbedding::embed(std::span<const float> mel) const {
  EmbeddingCache cache;
  return embed(mel, 0, cache);
}

Embedding SpeechEmbedding::embed(std::span<const float> mel, int shift, EmbeddingCache& cache) const {
  if (mel.size() != static_cast<std::size_t>(kEmbeddingFrames * kMelBins)) {
    throw std::invalid_argument("SpeechEmbedding::embed: " + std::to_string(mel.size()) +
                                " values, expected 76 x 32 = 2432");
  }
  const std::vector<Layer>& layers = layers_->layers;
  // Incremental only when the window moved by a number of frames every pooling divides.
  bool incremental = cache.valid && shift > 0 && shift % 8 == 0 && shift < kEmbeddingFrames &&
                     layers_->incremental;
  if (cache.outputs.size() != layers.size()) {
    cache.outputs.assign(layers.size(), {});
    incremental = false;
  }
  Shape in{1, kEmbeddingFrames, kMelBins};
  cache.input.assign(mel.begin(), mel.end());
  const std::vector<float>* x = &cache.input;
  int d = shift;  // rows of the current input that are new (at its bottom)
  for (std::size_t k = 0; k < layers.size(); ++k) {
    const Layer& layer = layers[k];
    const Shape& shape = layers_->shapes[k];
    const bool in_place = layer.kind == Layer::Kind::leaky_relu ||
                          layer.kind == Layer::Kind::max_constant;
    std::vector<float>& out = in_place ? *const_cast<std::vector<float>*>(x) : cache.outputs[k];
    int row_begin = 0;
    if (layer.kind == Layer::Kind::max_pool) d /= layer.stride_h;
    if (incremental && d < shape.h) {
      row_begin = shape.h - d;
      if (!in_place) {
        // Old rows move up by d; only the new bottom rows are computed.
        for (int c = 0; c < shape.c; ++c) {
          float* base = out.data() + static_cast<std::size_t>(c * shape.h * shape.w);
          std::copy(base + static_cast<std::size_t>(d * shape.w),
                    base + static_cast<std::size_t>(shape.h * shape.w), base);
        }
      }
    } else if (!in_place) {
      out.assign(static_cast<std::size_t>(shape.c * shape.h * shape.w), 0.0f);
    }
    run_rows(layer, *x, in, row_begin, out, shape, cache.col, cache.scratch);
    x = &out;
    in = shape;
  }
  cache.valid = true;
  Embedding e{};
  std::copy_n(x->begin(), kEmbeddingSize, e.begin());
  return e;
}

std::shared_ptr<const EmbeddingModels> EmbeddingModels::load(const std::filesystem::path& dir) {
  require_embedding_models(dir);
  return std::make_shared<const EmbeddingModels>(EmbeddingModels{
      MelFrontEnd(dir / "melspectrogram.onnx"), SpeechEmbedding(dir / "embedding_model.onnx")});
}

// ---------------------------------------------------------------------------------------------
// Streaming

EmbeddingStream::EmbeddingStream(std::shared_ptr<const EmbeddingModels> models)
    : models_(std::move(models)) {
  reset();
}

void EmbeddingStream::reset() {
  audio_.clear();
  pending_.clear();
  mel_.assign(kEmbeddingFrames, {});
  for (auto& frame : mel_) frame.fill(1.0f);  // openWakeWord starts its buffer with ones
  seen_ = 0;
  skip_ = 0;
  cache_.valid = false;
}

std::size_t EmbeddingStream::push(std::span<const float> samples, std::vector<Embedding>& out) {
  std::size_t added = 0;
  std::vector<float> window(static_cast<std::size_t>(kEmbeddingFrames * kMelBins));
  for (const float s : samples) {
    pending_.push_back(s);
    if (pending_.size() < static_cast<std::size_t>(kEmbeddingHop)) continue;
    audio_.insert(audio_.end(), pending_.begin(), pending_.end());
    pending_.clear();
    seen_ += kEmbeddingHop;
    const std::size_t keep = kEmbeddingHop + kMelContext;
    if (audio_.size() > keep) audio_.erase(audio_.begin(), audio_.end() - static_cast<std::ptrdiff_t>(keep));
    const std::vector<float> mel = models_->mel.compute(audio_);
    const int shift = static_cast<int>(mel.size() / kMelBins);
    for (std::size_t f = 0; f < mel.size() / kMelBins; ++f) {
      std::array<float, kMelBins> frame{};
      for (int b = 0; b < kMelBins; ++b) frame[static_cast<std::size_t>(b)] = mel[f * kMelBins + static_cast<std::size_t>(b)] / 10.0f + 2.0f;
      mel_.push_back(frame);
      mel_.pop_front();
    }
    if (skip_ > 0) {
      --skip_;
      cache_.valid = false;
      continue;
    }
    for (std::size_t f = 0; f < mel_.size(); ++f) {
      std::copy(mel_[f].begin(), mel_[f].end(), window.begin() + static_cast<std::ptrdiff_t>(f * kMelBins));
    }
    out.push_back(models_->embedding.embed(window, shift, cache_));
    ++added;
  }
  return added;
}

}  // namespace marvin::perception::kws
