// A small statistical intent model: multinomial logistic regression over word-stem unigrams
// and bigrams, trained when skills load from their expanded templates and example sentences,
// plus a built-in class of out-of-scope requests (background_sentences()).
//
// Why this and not libfasttext: the model must be rebuilt in well under a second whenever a
// skill is installed, give the same weights for the same skills on every machine, and need
// no temporary files; fastText trains from a file with its own threads. A sparse softmax over
// a few thousand features does the same job here (it is fastText without the hidden layer).
//
// Determinism: features are numbered in order of first appearance, sentences are visited in
// an order drawn from a fixed-seed std::mt19937 (whose sequence the standard fixes) with our
// own shuffle, and all arithmetic is single-threaded float. Same sentences in, same weights.
#pragma once

#include <string>
#include <unordered_map>
#include <vector>

#include "interpret/interpreter.h"
#include "interpret/wordnet.h"

namespace marvin::interpret {

struct LabelledSentence {
  std::vector<std::string> words;  // normalised
  int label = 0;                   // 0..classes-1
};

// One input feature: "u <stem>", "b <stem> <stem>", "c <4 letters>", "w <WordNet concept>".
struct Feature {
  std::string name;
  float weight = 1.0F;
};

// Word or collocation -> its WordNet concepts, filled while training.
using ConceptCache = std::unordered_map<std::string, std::vector<std::string>>;

class IntentModel {
 public:
  // Trains on `sentences` over `classes` classes. With `wordnet`, content words (and
  // WordNet collocations) also give their concepts as features (wordnet.h), so a word the
  // sentences never used counts through a synonym or hypernym that they did; the model keeps
  // the pointer, which must outlive it (WordNet::installed() does).
  static IntentModel train(const std::vector<LabelledSentence>& sentences, int classes,
                           const WordNet* wordnet = nullptr);

  // Probability of each class (sums to 1). An empty model gives a uniform answer.
  std::vector<float> probabilities(const std::vector<std::string>& words) const;

  int classes() const { return classes_; }
  std::size_t features() const { return feature_ids_.size(); }
  // Bytes held by the model (weights and feature table), for the benchmark.
  std::size_t memory_bytes() const;

 private:
  std::vector<std::pair<int, float>> active(const std::vector<std::string>& words, bool add,
                                            ConceptCache* cache);

  std::unordered_map<std::string, int> feature_ids_;
  std::vector<float> weights_;  // feature-major: weights_[feature * classes_ + class]
  std::vector<float> bias_;
  int classes_ = 0;
  const WordNet* wordnet_ = nullptr;
};

// The words the model sees for one normalised word: its stem, numbers as "#num".
std::string model_token(const std::string& word);

// Out-of-scope requests (weather, music, recipes, trivia, banking, ...) written for Marvin;
// they teach the model what "none of the skills" looks like.
const std::vector<std::string>& background_sentences();

// Answers people give in a dialogue (yes, no, say that again), as the model learns them:
// kYes, kNo, kRepeat (anything else gives the kRepeat list).
const std::vector<std::string>& dialogue_sentences(Builtin kind);

}  // namespace marvin::interpret
