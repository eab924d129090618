// Training cnn-trad-fpool3: mini-batch Adam on the softmax cross-entropy, with Eigen.
//
// The forward pass is the float network of network.h written for a batch (im2col + GEMM);
// the backward pass is its exact gradient. A batch is split between `threads` workers, each
// computing the gradient of its share; the shares are summed in a fixed order, so a run is
// deterministic for a given seed, data and thread count.
#pragma once

#include <cstdint>
#include <functional>
#include <random>
#include <span>
#include <vector>

#include "perception/kws/model_file.h"
#include "perception/kws/network.h"

namespace marvin::perception::kws {

// Examples as rows: inputs.size() == labels.size() * kInputSize.
struct TrainingSet {
  std::vector<float> inputs;
  std::vector<int> labels;
  std::size_t size() const { return labels.size(); }
  std::span<const float> input(std::size_t i) const {
    return std::span<const float>(inputs).subspan(i * kInputSize, kInputSize);
  }
};

struct TrainOptions {
  int batch_size = 32;
  float learning_rate = 1e-3f;
  float beta1 = 0.9f;
  float beta2 = 0.999f;
  float epsilon = 1e-8f;
  float weight_decay = 0.0f;  // L2, added to the gradient
  int threads = 2;
  // SpecAugment-style masking (Park et al. 2019), drawn anew for every example in every
  // epoch: one band of 0..freq_mask_bins mel bins and one span of 0..time_mask_frames input
  // frames are set to 0, the normalised mean, so the network cannot lean on a single band or
  // moment. 0 and 0 = off (models/README.md has what it did for espeak-ng voices).
  int freq_mask_bins = 0;
  int time_mask_frames = 0;
  // Vocal tract length perturbation (Jaitly & Hinton 2013), also drawn anew for every
  // example in every epoch: the mel axis is warped by a factor log-uniform in
  // [1/(1+freq_warp), 1+freq_warp], as if the speaker's formants sat that much higher or
  // lower. 0 = off.
  float freq_warp = 0.0f;
};

// The mask train_epoch() applies to one normalised input (kInputSize values, frame-major):
// a band and a span as above, chosen by `seed` alone.
void spec_mask(std::span<float> input, int freq_mask_bins, int time_mask_frames,
               std::uint64_t seed);

// Warps one input's frequency axis by `factor` (> 1 moves energy up, like a shorter vocal
// tract): output bin i takes the value at frequency f_i / factor, where f_i is bin i's centre
// frequency of the default LogMelOptions, interpolated linearly between the neighbouring
// bins' centres and held at the edge bins beyond them. factor 1 changes nothing. The trainer
// warps normalised inputs: the per-bin means vary slowly across bins, so that is close to
// warping the log-mel energies themselves.
void warp_frequency(std::span<float> input, float factor);

struct EpochStats {
  double loss = 0.0;      // mean cross-entropy over the epoch
  double accuracy = 0.0;  // fraction of training examples classified right (before the step)
};

class Trainer {
 public:
  Trainer(FloatNetwork& net, const TrainOptions& options);
  ~Trainer();

  // One pass over `data` in an order shuffled with `rng`. `progress(done, total, loss, acc)`
  // is called after every batch (may be empty).
  EpochStats train_epoch(
      const TrainingSet& data, std::mt19937_64& rng,
      const std::function<void(std::size_t, std::size_t, double, double)>& progress);

  // Mean loss and the gradient of one batch (for tests against finite differences).
  double loss_and_gradient(const TrainingSet& data, std::span<const std::size_t> batch,
                           FloatNetwork& gradient, std::size_t* correct = nullptr);

  void set_learning_rate(float lr) { options_.learning_rate = lr; }

 private:
  struct Worker;
  void adam_step(const FloatNetwork& gradient);

  FloatNetwork& net_;
  TrainOptions options_;
  FloatNetwork m_, v_;
  std::int64_t step_ = 0;
  std::uint64_t augment_seed_ = 0;  // of the current batch, when masking or warping is on
  std::vector<std::unique_ptr<Worker>> workers_;
};

// Fraction of examples whose most probable class is the label, and the confusion per class
// (counts[label][predicted]). Runs the float or int8 inference.
struct Accuracy {
  double overall = 0.0;
  std::array<std::array<int, kClasses>, kClasses> confusion{};
  double per_class(int cls) const;
};
Accuracy evaluate_float(const FloatNetwork& net, const TrainingSet& data);
Accuracy evaluate_int8(const QuantizedNetwork& net, const TrainingSet& data);

// Activation scales for int8: for each tensor, the `percentile` (0..1) of the per-example
// largest |value| over `data` (at most `max_examples` of them), divided by 127.
ActivationScales calibrate(const FloatNetwork& net, const TrainingSet& data,
                           double percentile = 0.999, std::size_t max_examples = 2000);

}  // namespace marvin::perception::kws
