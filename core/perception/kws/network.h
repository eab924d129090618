// The keyword spotter's network: cnn-trad-fpool3 (Sainath & Parada, "Convolutional Neural
// Networks for Small-footprint Keyword Spotting", Interspeech 2015), float and int8.
//
// Input: one window of about 1 s of 40-bin log-mel frames (log_mel.h defaults: 25 ms / 10 ms):
// 96 frames, 15600 samples. The paper's network sees 32 frames; we keep its size (about 245 K
// parameters, 9.7 M multiply-accumulates) and the 1 s of context by averaging every 3
// consecutive frames, then normalising each bin with the mean and scale stored in the model
// (features.h). So the input is 32 x 40, time-major.
//
//   conv1   20 (time) x 8 (freq) x 64 maps, stride 1, ReLU      -> 13 x 33 x 64
//   pool    max over 3 frequencies (stride 3)                  -> 13 x 11 x 64
//   conv2   10 x 4 x 64 -> 64 maps, stride 1, ReLU              ->  4 x  8 x 64  (2048)
//   linear  2048 -> 32, no non-linearity (the paper's low-rank layer)
//   dense   32 -> 128, ReLU
//   output  128 -> 4 logits, softmax: keyword, unknown word, silence, noise
//
// Activations are stored time-major, channels last: a1[t][f][c], a2[(t*8+f)*64+c].
// Every weight matrix is [out][in], row-major; conv1's `in` index is dt*8+df, conv2's is
// (dt*4+df)*64+ic.
//
// int8 (QuantizedNetwork): real = int8 * scale with zero point 0. Weights have one scale per
// output channel (per-tensor is the special case of all scales equal); activations one
// scale per tensor, calibrated on training data. Products are accumulated in int32; the
// bias is added in accumulator units and the sum rescaled to the next layer's int8 scale.
// The output layer's accumulators are rescaled to float logits.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "perception/kws/gemm_avx2.h"
#include "perception/kws/gemm_avx512.h"

namespace marvin::perception::kws {

// Shapes (fixed by the architecture).
inline constexpr int kInputFrames = 32;    // network input frames (after averaging)
inline constexpr int kFramesPerInput = 3;  // log-mel frames averaged into one input frame
inline constexpr int kWindowFrames = kInputFrames * 3;  // 96 log-mel frames per window
inline constexpr int kBins = 40;
inline constexpr int kConv1Time = 20, kConv1Freq = 8, kConv1Maps = 64;
inline constexpr int kPoolFreq = 3;
inline constexpr int kConv1OutTime = kInputFrames - kConv1Time + 1;  // 13
inline constexpr int kConv1OutFreq = kBins - kConv1Freq + 1;         // 33
inline constexpr int kPooledFreq = kConv1OutFreq / kPoolFreq;        // 11
inline constexpr int kConv2Time = 10, kConv2Freq = 4, kConv2Maps = 64;
inline constexpr int kConv2OutTime = kConv1OutTime - kConv2Time + 1;      // 4
inline constexpr int kConv2OutFreq = kPooledFreq - kConv2Freq + 1;        // 8
inline constexpr int kFlat = kConv2OutTime * kConv2OutFreq * kConv2Maps;  // 2048
inline constexpr int kLinear = 32;
inline constexpr int kDense = 128;
inline constexpr int kClasses = 4;
inline constexpr int kInputSize = kInputFrames * kBins;                // 1280
inline constexpr int kConv1In = kConv1Time * kConv1Freq;               // 160
inline constexpr int kConv2In = kConv2Time * kConv2Freq * kConv1Maps;  // 2560

enum class KwsClass : int { keyword = 0, unknown = 1, silence = 2, noise = 3 };
const char* class_name(int cls);  // "keyword", "unknown", "silence", "noise"

// One fully connected or convolution layer in float: weights [out][in], bias [out].
struct FloatLayer {
  int out = 0;
  int in = 0;
  std::vector<float> weights;
  std::vector<float> bias;
};

struct FloatNetwork {
  FloatLayer conv1{kConv1Maps, kConv1In, {}, {}};
  FloatLayer conv2{kConv2Maps, kConv2In, {}, {}};
  FloatLayer linear{kLinear, kFlat, {}, {}};
  FloatLayer dense{kDense, kLinear, {}, {}};
  FloatLayer output{kClasses, kDense, {}, {}};

  // The five layers in order (for loops over layers: files, optimisers).
  std::array<FloatLayer*, 5> layers() { return {&conv1, &conv2, &linear, &dense, &output}; }
  std::array<const FloatLayer*, 5> layers() const {
    return {&conv1, &conv2, &linear, &dense, &output};
  }
  std::size_t parameter_count() const;
};

// Sizes every layer and draws He-uniform weights, zero biases, from `seed`.
FloatNetwork make_initialised_network(std::uint64_t seed);

// Activation scales (real = int8 * scale) for the input and each layer's output.
struct ActivationScales {
  float input = 0.0f;
  float conv1 = 0.0f;  // after ReLU and pooling
  float conv2 = 0.0f;
  float linear = 0.0f;
  float dense = 0.0f;
};

struct QuantizedLayer {
  int out = 0;
  int in = 0;
  std::vector<std::int8_t> weights;  // [out][in]
  std::vector<float> weight_scales;  // [out]
  std::vector<float> bias;           // [out], real units
};

struct QuantizedNetwork {
  QuantizedLayer conv1, conv2, linear, dense, output;
  ActivationScales scales;

  std::array<QuantizedLayer*, 5> layers() { return {&conv1, &conv2, &linear, &dense, &output}; }
  std::array<const QuantizedLayer*, 5> layers() const {
    return {&conv1, &conv2, &linear, &dense, &output};
  }
};

enum class WeightScaling { per_tensor, per_channel };

// Symmetric int8 quantisation of a layer: scale = max|w| / 127 (per channel or per tensor).
QuantizedLayer quantize_layer(const FloatLayer& layer, WeightScaling scaling);
// The float layer the int8 weights stand for (weights * scale).
FloatLayer dequantize_layer(const QuantizedLayer& layer);

QuantizedNetwork quantize(const FloatNetwork& net, const ActivationScales& scales,
                          WeightScaling scaling = WeightScaling::per_channel);
FloatNetwork dequantize(const QuantizedNetwork& net);

// Runs the float network on one input (kInputSize values, already normalised). Holds its
// scratch buffers: nothing is allocated per call. Not thread-safe; one per thread.
class FloatInference {
 public:
  explicit FloatInference(const FloatNetwork& net);
  // Writes kClasses probabilities (softmax) to `probabilities`.
  void run(std::span<const float> input, std::span<float> probabilities);
  // Largest |value| after each layer of the last run(), for calibration.
  const ActivationScales& last_ranges() const { return ranges_; }

 private:
  FloatNetwork net_;
  std::vector<float> cols1_, z1_, a1_, cols2_, a2_, l_, h_;
  ActivationScales ranges_;
};

// The int8 x int8 -> int32 kernels Int8Inference can use, fastest last.
enum class Int8Kernel { portable, avx2, avx512_vnni };
const char* kernel_name(Int8Kernel kernel);  // "portable", "AVX2", "AVX-512 VNNI"
// True when this build and this CPU can run `kernel`.
bool kernel_available(Int8Kernel kernel);
// The fastest available kernel (checked once).
Int8Kernel best_int8_kernel();

// Runs the int8 network. The input is quantised with scales.input; everything after it is
// int8 x int8 -> int32. Uses the fastest kernel the CPU has (AVX-512 VNNI, else AVX2, else
// portable loops); all give bit-identical results. The two vector paths share one plan:
// weights packed once for the kernel, im2col fused, conv2 on bytes (gemm_avx512.h,
// gemm_avx2.h). Holds its scratch buffers and the weights
// packed for its kernel: nothing is allocated per call. Not thread-safe; one per thread.
class Int8Inference {
 public:
  explicit Int8Inference(const QuantizedNetwork& net);
  void run(std::span<const float> input, std::span<float> probabilities);

  // The kernel in use.
  Int8Kernel kernel() const { return kernel_; }
  // True when a vectorised (AVX2 or AVX-512) kernel is in use.
  bool vectorised() const { return kernel_ != Int8Kernel::portable; }
  // Chooses the kernel (tests compare them). Throws std::invalid_argument naming the kernel
  // when this CPU or build lacks it; the kernel in use is then unchanged.
  void set_kernel(Int8Kernel kernel);
  // Forces the portable kernel, or goes back to the fastest one.
  void set_portable(bool portable) {
    set_kernel(portable ? Int8Kernel::portable : best_int8_kernel());
  }

 private:
  struct Layer {
    int out = 0, in = 0;
    std::vector<std::int16_t> weights;  // int8 values widened for the multiply-add kernel
    std::vector<std::int32_t> bias;     // in accumulator units
    std::vector<float> to_real;         // accumulator -> real value, per output channel
    detail::PackedS16 packed;           // AVX-512 kernel, dense layers (convs: below)
    detail::Packed256S16 packed256;     // AVX2 kernel, dense layers (convs: below)
  };
  void gemm(const std::int16_t* a, int rows, const Layer& layer, std::int32_t* c) const;
  void run_avx512(std::span<const float> input, std::span<float> probabilities);
  void run_avx2(std::span<const float> input, std::span<float> probabilities);

  Layer conv1_, conv2_, linear_, dense_, output_;
  ActivationScales scales_;
  Int8Kernel kernel_ = Int8Kernel::portable;
  std::vector<std::int16_t> cols1_, a1_, cols2_, a2_, l_, h_;
  std::vector<std::int32_t> acc_;
  // Where each output position's receptive field starts in the input / in a1 (AVX-512 path).
  std::vector<std::int32_t> conv1_rows_, conv2_rows_;
  // AVX-512 path: both convolutions read their input as bytes (conv1's shifted by +128, which
  // conv1_shifted_bias_ takes back out), with their weights packed for that.
  detail::PackedS8 conv1_bytes_, conv2_bytes_;
  std::vector<std::int32_t> conv1_shifted_bias_;
  std::vector<std::uint8_t> a1_bytes_;
  // AVX2 path: conv1 on int16 (its signed input would saturate vpmaddubsw), conv2 on bytes
  // (a1_bytes_, 0..127), both packed once.
  detail::Packed256S16 conv1_avx2_;
  detail::Packed256S8 conv2_avx2_;
};

// The int8 x int8 -> int32 matrix kernels of Int8Inference, one per Int8Kernel:
// c[m*cols + j] = sum_k a[m*depth + k] * w[j*depth + k], for m < rows, j < cols. All take
// any sizes (the vector kernels pad the packed weights to whole groups and blocks).
void gemm_s16_portable(const std::int16_t* a, int rows, const std::int16_t* w, int cols, int depth,
                       std::int32_t* c);
bool gemm_s16_avx2_available();
// Packs `w` on every call (Int8Inference packs once); throws std::logic_error if not built.
void gemm_s16_avx2(const std::int16_t* a, int rows, const std::int16_t* w, int cols, int depth,
                   std::int32_t* c);
// Bytes x int8 with vpmaddubsw: exact only for activations 0..127 (gemm_avx2.h says why).
// Int8Inference uses it for conv2, whose input is ReLU'd and clamped to 127.
void gemm_u8s8_avx2(const std::uint8_t* a, int rows, const std::int16_t* w, int cols, int depth,
                    std::int32_t* c);
bool gemm_s16_avx512_available();
// Packs `w` on every call (Int8Inference packs once); throws std::logic_error if not built.
void gemm_s16_avx512(const std::int16_t* a, int rows, const std::int16_t* w, int cols, int depth,
                     std::int32_t* c);
// The same for activations that are never negative (after a ReLU), held as bytes 0..255:
// twice the multiply-adds per instruction. Int8Inference uses it for conv2.
void gemm_u8s8_avx512(const std::uint8_t* a, int rows, const std::int16_t* w, int cols, int depth,
                      std::int32_t* c);

// Softmax in place.
void softmax(std::span<float> values);

}  // namespace marvin::perception::kws
