#include "interpret/intent_model.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>

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

std::vector<std::string> feature_strings(const std::vector<std::string>& words) {
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
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
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

std::vector<int> IntentModel::active(const std::vector<std::string>& words, bool add) {
  std::vector<int> ids;
  for (const std::string& f : feature_strings(words)) {
    auto it = feature_ids_.find(f);
    if (it != feature_ids_.end()) {
      ids.push_back(it->second);
    } else if (add) {
      int id = static_cast<int>(feature_ids_.size());
      feature_ids_.emplace(f, id);
      ids.push_back(id);
    }
  }
  return ids;
}

IntentModel IntentModel::train(const std::vector<LabelledSentence>& sentences, int classes) {
  IntentModel model;
  model.classes_ = classes;
  const auto c = static_cast<std::size_t>(classes);
  std::vector<std::vector<int>> inputs;
  inputs.reserve(sentences.size());
  for (const LabelledSentence& s : sentences) inputs.push_back(model.active(s.words, true));
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
      const std::vector<int>& x = inputs[index];
      if (x.empty()) continue;
      const float value = 1.0F / std::sqrt(static_cast<float>(x.size()));
      for (std::size_t k = 0; k < c; ++k) scores[k] = model.bias_[k];
      for (int f : x) {
        const float* row = &model.weights_[static_cast<std::size_t>(f) * c];
        for (std::size_t k = 0; k < c; ++k) scores[k] += row[k] * value;
      }
      softmax(scores);
      const auto label = static_cast<std::size_t>(sentences[index].label);
      for (std::size_t k = 0; k < c; ++k) {
        float gradient = scores[k] - (k == label ? 1.0F : 0.0F);
        model.bias_[k] -= rate * gradient * 0.1F;
        scores[k] = gradient;
      }
      for (int f : x) {
        float* row = &model.weights_[static_cast<std::size_t>(f) * c];
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
  std::vector<int> x;
  for (const std::string& f : feature_strings(words)) {
    auto it = feature_ids_.find(f);
    if (it != feature_ids_.end()) x.push_back(it->second);
  }
  if (!x.empty()) {
    const float value = 1.0F / std::sqrt(static_cast<float>(x.size()));
    for (int f : x) {
      const float* row = &weights_[static_cast<std::size_t>(f) * c];
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
