// Training the embedding wake word's head (embedding_head.h): mini-batch Adam on weighted
// binary cross-entropy, He initialisation, all from one seed, single-threaded (so a seed gives
// the same head on one machine). Used by tools/kws and the tests, not by the robot.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "perception/kws/embedding_head.h"

namespace marvin::perception::kws {

// Examples: 1536 numbers each (16 embeddings, oldest first) and a 0/1 label.
struct HeadSet {
  std::vector<float> inputs;
  std::vector<float> labels;
  std::size_t size() const { return labels.size(); }
  void add(std::span<const float> input, float label);
  void append(const HeadSet& other);
};

struct HeadTrainOptions {
  int hidden = 32;
  int epochs = 20;
  int batch = 128;
  float learning_rate = 1e-3f;
  float weight_decay = 1e-4f;
  // Weight of each positive example's loss relative to a negative's (negatives outnumber
  // positives; a false accept costs more than a miss, so not fully balanced by default).
  float positive_weight = 1.0f;
  std::uint64_t seed = 1;
  // Called after each batch: (epoch, batches done, batches per epoch, mean loss so far).
  std::function<void(int, std::size_t, std::size_t, double)> progress;
};

EmbeddingHead train_head(const HeadSet& train, const HeadTrainOptions& options);

struct HeadAccuracy {
  double positives = 0.0;  // fraction of positives scored >= threshold
  double negatives = 0.0;  // fraction of negatives scored < threshold
};
HeadAccuracy head_accuracy(const EmbeddingHead& head, const HeadSet& set, float threshold);

}  // namespace marvin::perception::kws
