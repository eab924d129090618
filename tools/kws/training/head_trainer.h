// Training the embedding wake word's head (embedding_head.h): mini-batch Adam on weighted
// binary cross-entropy, He initialisation, all from one seed, single-threaded (so a seed gives
// the same head on one machine). Used by tools/kws and the tests, not by the robot.
#pragma once

#include <cstdint>
#include <filesystem>
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
  // Weight of a negative's loss in the last epoch, reached linearly from 1 in the first
  // (openWakeWord raises the negative weight as training goes on: first learn the keyword,
  // then push the false accepts down). 1 keeps it constant.
  float final_negative_weight = 1.0f;
  std::uint64_t seed = 1;
  // Called after each batch: (epoch, batches done, batches per epoch, mean loss so far).
  std::function<void(int, std::size_t, std::size_t, double)> progress;
};

// The feature cache: a HeadSet on disk, so that retraining skips synthesis and embedding.
// Format (little-endian): "MKWSFEAT", uint32 version 1, uint32 inputs per example (1536),
// uint64 example count n, then n float labels, then n x 1536 float inputs.
void save_head_set(const std::filesystem::path& path, const HeadSet& set);
// Throws ModelFileError naming the file and what is wrong (magic, version, size, truncation).
HeadSet load_head_set(const std::filesystem::path& path);

EmbeddingHead train_head(const HeadSet& train, const HeadTrainOptions& options);

// One head whose score is the sigmoid of the members' mean logit (an ensemble of heads trained
// with different seeds or data: their chance false accepts differ, a keyword scores high in all
// of them). Exact, in the same file format: the hidden layers side by side, the second one
// block-diagonal, the output weights divided by the number of members. Keyword and detection
// settings are the first member's. Throws std::invalid_argument when there are no members,
// their keywords differ, or their hidden units add up to more than the format's 1024.
EmbeddingHead merge_heads(const std::vector<EmbeddingHead>& members);

struct HeadAccuracy {
  double positives = 0.0;  // fraction of positives scored >= threshold
  double negatives = 0.0;  // fraction of negatives scored < threshold
};
HeadAccuracy head_accuracy(const EmbeddingHead& head, const HeadSet& set, float threshold);

}  // namespace marvin::perception::kws
