// The front end of the embedding wake word (issue 21): openWakeWord's mel spectrogram and
// Google's speech_embedding network, run by our own code from the two ONNX files npm ships
// (scripts/fetch-kws-models puts them in .cache/kws).
//
// - MelFrontEnd reproduces melspectrogram.onnx: frames of 512 samples every 160 (10 ms at
//   16 kHz), the graph's own windowed DFT weights (a convolution with 257 real and 257
//   imaginary filters), power, the graph's 257 x 32 mel matrix, clip at 1e-10, 10 log10, and
//   the top-80-dB floor relative to the loudest value of the call. Input is in int16 units
//   (a float sample s in [-1, 1] is s * 32768), as openWakeWord feeds it.
// - SpeechEmbedding reproduces embedding_model.onnx: 76 mel frames x 32 bins (after
//   openWakeWord's scaling x / 10 + 2) -> 96 numbers, through 20 convolutions with
//   LeakyReLU(0.2) and max(x, -0.4), and 5 max-poolings. The graph is read node by node and
//   checked: any operator or shape other than those refuses to load with a message naming the
//   file and node.
// - EmbeddingStream is openWakeWord's streaming: every 1280 samples (80 ms) the mel of the
//   last 1760 samples (8 new frames) joins a 76-frame buffer (starting as ones) and one
//   embedding of those 76 frames comes out.
//
// Proof against the originals (onnxruntime): tools/kws/check-embedding; figures in
// models/README.md. Thread safety: const member functions of a loaded object may run on
// several threads at once; EmbeddingStream is one stream's state.
#pragma once

#include <array>
#include <cstdint>
#include <deque>
#include <filesystem>
#include <memory>
#include <span>
#include <vector>

namespace marvin::perception::kws {

inline constexpr int kMelBins = 32;
inline constexpr int kEmbeddingFrames = 76;   // mel frames per embedding
inline constexpr int kEmbeddingSize = 96;
inline constexpr int kEmbeddingHop = 1280;    // samples between embeddings (80 ms)
inline constexpr int kMelContext = 480;       // extra samples the mel of a hop looks back

using Embedding = std::array<float, kEmbeddingSize>;

// Where the ONNX files are: $MARVIN_KWS_EMBEDDING_DIR if set, else .cache/kws of the source
// tree this library was built from (scripts/setup fills it).
std::filesystem::path embedding_model_dir();

// Throws std::runtime_error naming the first missing file of `dir` and scripts/setup.
void require_embedding_models(const std::filesystem::path& dir);

class MelFrontEnd {
 public:
  // Reads and checks melspectrogram.onnx; throws OnnxError (onnx_file.h).
  explicit MelFrontEnd(const std::filesystem::path& onnx_file);
  ~MelFrontEnd();
  MelFrontEnd(MelFrontEnd&&) noexcept;

  // The graph's output for `samples` (int16 units): frames x 32 values, frame-major, where
  // frames = (samples - 512) / 160 + 1 (0 when fewer than 512 samples). No x / 10 + 2.
  std::vector<float> compute(std::span<const float> samples) const;
  static std::size_t frames_for(std::size_t samples);

 private:
  struct Weights;
  std::unique_ptr<Weights> w_;
};

// Every layer's output for the last window a stream embedded, so that the next window, 8 mel
// frames later, computes only its new rows (about 6x fewer multiply-accumulates).
struct EmbeddingCache {
  bool valid = false;
  std::vector<float> input;
  std::vector<std::vector<float>> outputs;
  std::vector<float> col, scratch;
};

class SpeechEmbedding {
 public:
  // Reads and checks embedding_model.onnx; throws OnnxError.
  explicit SpeechEmbedding(const std::filesystem::path& onnx_file);
  ~SpeechEmbedding();
  SpeechEmbedding(SpeechEmbedding&&) noexcept;

  // `mel`: 76 x 32 values, frame-major, scaled x / 10 + 2. Returns the 96 numbers.
  Embedding embed(std::span<const float> mel) const;
  // The same for a stream: `mel` is the window before, in `cache`, moved by `shift` frames
  // (the new frames at the end). Shifts other than multiples of 8, or an empty cache, compute
  // everything. Results equal embed(mel)'s to float rounding.
  Embedding embed(std::span<const float> mel, int shift, EmbeddingCache& cache) const;

  // Multiply-accumulates per embedding (for the cost figures).
  std::int64_t macs() const;

 private:
  struct Layers;
  std::unique_ptr<Layers> layers_;
};

// Both models, loaded once and shared by streams.
struct EmbeddingModels {
  MelFrontEnd mel;
  SpeechEmbedding embedding;
  // Loads dir/melspectrogram.onnx and dir/embedding_model.onnx (require_embedding_models
  // first, so a missing file names scripts/setup).
  static std::shared_ptr<const EmbeddingModels> load(const std::filesystem::path& dir =
                                                         embedding_model_dir());
};

class EmbeddingStream {
 public:
  explicit EmbeddingStream(std::shared_ptr<const EmbeddingModels> models);

  // Feeds samples in int16 units; appends one embedding per completed 80 ms hop. Returns
  // how many were appended.
  std::size_t push(std::span<const float> samples, std::vector<Embedding>& out);
  void reset();
  // The next `hops` hops update the mel buffer but embed nothing (training examples need only
  // their last embeddings; saves the work of the others).
  void skip_embeddings(std::size_t hops) { skip_ = hops; }
  // Samples consumed since construction or reset (the end of the last embedding's audio
  // is at a multiple of kEmbeddingHop).
  std::int64_t samples_seen() const { return seen_; }

 private:
  std::shared_ptr<const EmbeddingModels> models_;
  std::vector<float> audio_;    // the last kEmbeddingHop + kMelContext samples at most
  std::vector<float> pending_;  // samples of the hop in progress
  std::deque<std::array<float, kMelBins>> mel_;  // the last 76 scaled frames
  std::int64_t seen_ = 0;
  EmbeddingCache cache_;
  std::size_t skip_ = 0;
};

}  // namespace marvin::perception::kws
