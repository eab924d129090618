#include "interpret/intent_model.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <random>
#include <string_view>

#include "interpret/phrasing.h"

namespace marvin::interpret {
namespace {

// Passes over the data: 30 for a robot's usual few thousand sentences, fewer for many skills
// so a build stays well under a second (about kUpdateBudget sentence updates in all).
constexpr int kMaxEpochs = 30;
constexpr int kMinEpochs = 4;
constexpr std::size_t kUpdateBudget = 60000;
constexpr float kLearningRate = 0.4F;
constexpr float kL2 = 1e-5F;

bool is_number_token(const std::string& word) {
  return !word.empty() && word[0] >= '0' && word[0] <= '9';
}

// Function words WordNet also lists ("can" the container, "will" the document, "i" iodine):
// their concepts would only add noise.
bool is_function_word(const std::string& w) {
  static const std::array<std::string_view, 62> kWords{
      "a",    "about", "all", "am",    "an",    "and",  "any",   "are",   "as",   "at",   "be",
      "been", "but",   "by",  "can",   "could", "did",  "do",    "does",  "for",  "from", "had",
      "has",  "have",  "he",  "her",   "him",   "his",  "how",   "i",     "if",   "in",   "is",
      "it",   "its",   "me",  "my",    "no",    "not",  "of",    "on",    "or",   "our",  "she",
      "so",   "that",  "the", "their", "them",  "then", "there", "these", "they", "this", "to",
      "up",   "was",   "we",  "what",  "will",  "with", "you"};
  return w.size() < 3 || std::find(kWords.begin(), kWords.end(), w) != kWords.end();
}

// Measured on half a of the development set (core/interpret/README.md): the synsets of a
// word's three most frequent senses, as strong as the word itself; hypernyms did not help
// (they are too broad: "lock" -> "fasten", "time" -> "case").
constexpr float kConceptWeight = 1.0F;
constexpr int kSenses = 3;
constexpr int kHypernymSenses = 0;

std::vector<Feature> feature_list(const std::vector<std::string>& words, const WordNet* wordnet,
                                  ConceptCache* cache) {
  std::vector<std::string> tokens;
  tokens.reserve(words.size());
  for (const std::string& w : words) tokens.push_back(model_token(w));
  std::vector<std::string> out;
  out.reserve(tokens.size() * 2 + 2);
  for (const std::string& t : tokens) {
    out.push_back("u " + t);
    // Character 4-grams: unseen forms of known words ("schedules", "scheduling") still count.
    if (t.size() >= 4 && t[0] != '#') {
      std::string marked = "<" + t + ">";
      for (std::size_t i = 0; i + 4 <= marked.size(); ++i) out.push_back("c " + marked.substr(i, 4));
    }
  }
  std::string previous = "<s>";
  for (const std::string& t : tokens) {
    out.push_back("b " + previous + " " + t);
    previous = t;
  }
  out.push_back("b " + previous + " </s>");
  std::vector<std::string> concepts;
  if (wordnet != nullptr) {
    auto concepts_of = [&](const std::string& phrase) -> std::vector<std::string> {
      if (cache == nullptr) return wordnet->concepts(phrase, kSenses, kHypernymSenses);
      auto it = cache->find(phrase);
      if (it == cache->end())
        it = cache->emplace(phrase, wordnet->concepts(phrase, kSenses, kHypernymSenses)).first;
      return it->second;
    };
    for (std::size_t i = 0; i < words.size(); ++i) {
      // Collocations first ("bear in mind", "turn off"): their own senses, not their words'.
      for (std::size_t n = 3; n >= 2; --n) {
        if (i + n > words.size()) continue;
        std::string phrase = words[i];
        for (std::size_t k = 1; k < n; ++k) phrase += " " + words[i + k];
        for (std::string& c : concepts_of(phrase)) concepts.push_back("w " + c);
      }
      if (is_function_word(words[i]) || is_number_token(words[i])) continue;
      for (std::string& c : concepts_of(words[i])) concepts.push_back("w " + c);
    }
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  std::sort(concepts.begin(), concepts.end());
  concepts.erase(std::unique(concepts.begin(), concepts.end()), concepts.end());
  std::vector<Feature> features;
  features.reserve(out.size() + concepts.size());
  for (std::string& f : out) features.push_back({std::move(f), 1.0F});
  for (std::string& f : concepts) features.push_back({std::move(f), kConceptWeight});
  return features;
}

// Inputs are scaled to unit length so long sentences do not shout.
float input_norm(const std::vector<std::pair<int, float>>& x) {
  float sum = 0;
  for (const auto& [f, weight] : x) sum += weight * weight;
  return sum > 0 ? 1.0F / std::sqrt(sum) : 0.0F;
}

void softmax(std::vector<float>& scores) {
  float top = *std::max_element(scores.begin(), scores.end());
  float sum = 0;
  for (float& s : scores) {
    s = std::exp(s - top);
    sum += s;
  }
  for (float& s : scores) s /= sum;
}

}  // namespace

std::string model_token(const std::string& word) {
  if (is_number_token(word)) {
    // "21st" stays an ordinal, "8", "7:30" and "2.5" are all numbers to the model.
    if (word.ends_with("st") || word.ends_with("nd") || word.ends_with("rd") ||
        word.ends_with("th")) {
      return "#ord";
    }
    return "#num";
  }
  return stem(word);
}

std::vector<std::pair<int, float>> IntentModel::active(const std::vector<std::string>& words,
                                                       bool add, ConceptCache* cache) {
  std::vector<std::pair<int, float>> ids;
  for (Feature& f : feature_list(words, wordnet_, cache)) {
    auto it = feature_ids_.find(f.name);
    if (it != feature_ids_.end()) {
      ids.emplace_back(it->second, f.weight);
    } else if (add) {
      int id = static_cast<int>(feature_ids_.size());
      feature_ids_.emplace(std::move(f.name), id);
      ids.emplace_back(id, f.weight);
    }
  }
  return ids;
}

IntentModel IntentModel::train(const std::vector<LabelledSentence>& sentences, int classes,
                               const WordNet* wordnet) {
  IntentModel model;
  model.classes_ = classes;
  model.wordnet_ = wordnet;
  const auto c = static_cast<std::size_t>(classes);
  std::vector<std::vector<std::pair<int, float>>> inputs;
  inputs.reserve(sentences.size());
  ConceptCache cache;
  for (const LabelledSentence& s : sentences) inputs.push_back(model.active(s.words, true, &cache));
  model.weights_.assign(model.feature_ids_.size() * c, 0.0F);
  model.bias_.assign(c, 0.0F);
  if (sentences.empty() || classes == 0) return model;

  std::vector<std::size_t> order(sentences.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::mt19937 random(20261125U);
  std::vector<float> scores(c);
  const int epochs = static_cast<int>(std::clamp<std::size_t>(
      kUpdateBudget / sentences.size(), kMinEpochs, kMaxEpochs));
  for (int epoch = 0; epoch < epochs; ++epoch) {
    // Fisher-Yates with our own index draws: std::shuffle's use of the engine is
    // implementation-defined.
    for (std::size_t i = order.size(); i > 1; --i) {
      std::size_t j = static_cast<std::size_t>(random() % i);
      std::swap(order[i - 1], order[j]);
    }
    const float rate = kLearningRate / (1.0F + static_cast<float>(epoch) * 0.5F);
    for (std::size_t index : order) {
      const std::vector<std::pair<int, float>>& x = inputs[index];
      if (x.empty()) continue;
      const float norm = input_norm(x);
      for (std::size_t k = 0; k < c; ++k) scores[k] = model.bias_[k];
      for (const auto& [f, weight] : x) {
        const float* row = &model.weights_[static_cast<std::size_t>(f) * c];
        const float value = weight * norm;
        for (std::size_t k = 0; k < c; ++k) scores[k] += row[k] * value;
      }
      softmax(scores);
      const auto label = static_cast<std::size_t>(sentences[index].label);
      for (std::size_t k = 0; k < c; ++k) {
        float gradient = scores[k] - (k == label ? 1.0F : 0.0F);
        model.bias_[k] -= rate * gradient * 0.1F;
        scores[k] = gradient;
      }
      for (const auto& [f, weight] : x) {
        float* row = &model.weights_[static_cast<std::size_t>(f) * c];
        const float value = weight * norm;
        for (std::size_t k = 0; k < c; ++k) {
          row[k] -= rate * (scores[k] * value + kL2 * row[k]);
        }
      }
    }
  }
  return model;
}

std::vector<float> IntentModel::probabilities(const std::vector<std::string>& words) const {
  const auto c = static_cast<std::size_t>(classes_);
  std::vector<float> scores(bias_);
  if (c == 0) return scores;
  std::vector<std::pair<int, float>> x;
  for (const Feature& f : feature_list(words, wordnet_, nullptr)) {
    auto it = feature_ids_.find(f.name);
    if (it != feature_ids_.end()) x.emplace_back(it->second, f.weight);
  }
  if (!x.empty()) {
    const float norm = input_norm(x);
    for (const auto& [f, weight] : x) {
      const float* row = &weights_[static_cast<std::size_t>(f) * c];
      const float value = weight * norm;
      for (std::size_t k = 0; k < c; ++k) scores[k] += row[k] * value;
    }
  }
  softmax(scores);
  return scores;
}

std::size_t IntentModel::memory_bytes() const {
  std::size_t bytes = (weights_.size() + bias_.size()) * sizeof(float);
  for (const auto& [name, id] : feature_ids_) bytes += name.capacity() + 48;
  return bytes;
}

}  // namespace marvin::interpret
