// The embedding wake word's front end (speech_embedding.h): our mel spectrogram and speech
// embedding against numbers onnxruntime computed with the original ONNX graphs on the same
// clips (tests/kws/data/*.ref.json, made by tools/kws/check-embedding with MARVIN_CHECK_KEEP),
// streaming as openWakeWord does it, and the errors for missing or damaged model files.
// Needs .cache/kws (scripts/setup fetches it, as for the vision models).
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "devices/audio/sound_file.h"
#include "perception/kws/onnx_file.h"
#include "perception/kws/speech_embedding.h"

namespace kws = marvin::perception::kws;
namespace fs = std::filesystem;

namespace {

fs::path embedding_data_dir() { return fs::path(MARVIN_TEST_SOURCE_DIR) / "tests/kws/data"; }

std::shared_ptr<const kws::EmbeddingModels> shared_models() {
  static const auto models = kws::EmbeddingModels::load(kws::embedding_model_dir());
  return models;
}

std::vector<float> clip_samples(const std::string& name) {
  const auto pcm = marvin::audio::read_speech_file(embedding_data_dir() / (name + ".flac"));
  return {pcm.begin(), pcm.end()};
}

nlohmann::json reference(const std::string& name) {
  std::ifstream in(embedding_data_dir() / (name + ".ref.json"));
  REQUIRE(in);
  return nlohmann::json::parse(in);
}

// Largest absolute difference over the reference's values / their largest magnitude.
double relative_difference(const std::vector<float>& ours, const nlohmann::json& ref) {
  double diff = 0.0, mag = 0.0;
  for (std::size_t k = 0; k < ref.size(); ++k) {
    const double r = ref[k].get<double>();
    diff = std::max(diff, std::abs(static_cast<double>(ours.at(k)) - r));
    mag = std::max(mag, std::abs(r));
  }
  return diff / mag;
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("mel front end and embedding match onnxruntime on the stored clips") {
  const auto models = shared_models();
  for (const std::string name : {"marvin_en_us", "weather_en_f3"}) {
    CAPTURE(name);
    const std::vector<float> samples = clip_samples(name);
    const nlohmann::json ref = reference(name);
    REQUIRE(samples.size() == ref["samples"].get<std::size_t>());
    const std::vector<float> mel = models->mel.compute(samples);
    CHECK(mel.size() / kws::kMelBins == ref["mel_frames"].get<std::size_t>());
    CHECK(relative_difference(mel, ref["mel_first"]) < 1e-4);
    // The first windows: every 8th 76-frame window, scaled as openWakeWord does.
    std::vector<float> embeddings;
    for (std::size_t w = 0; w < ref["embedding_first"].size() / kws::kEmbeddingSize; ++w) {
      std::vector<float> window(mel.begin() + static_cast<std::ptrdiff_t>(w * 8 * kws::kMelBins),
                                mel.begin() + static_cast<std::ptrdiff_t>((w * 8 + kws::kEmbeddingFrames) *
                                                                          kws::kMelBins));
      for (float& v : window) v = v / 10.0f + 2.0f;
      const kws::Embedding e = models->embedding.embed(window);
      embeddings.insert(embeddings.end(), e.begin(), e.end());
    }
    CHECK(embeddings.size() == 4 * kws::kEmbeddingSize);
    CHECK(relative_difference(embeddings, ref["embedding_first"]) < 1e-4);
  }
}

TEST_CASE("embedding a window moved by 8 frames reuses the last one's rows and gives the same numbers") {
  const auto models = shared_models();
  const std::vector<float> mel = models->mel.compute(clip_samples("weather_en_f3"));
  kws::EmbeddingCache cache;
  int windows = 0;
  double worst = 0.0;
  for (std::size_t first = 0; (first + kws::kEmbeddingFrames) * kws::kMelBins <= mel.size(); first += 8) {
    std::vector<float> window(mel.begin() + static_cast<std::ptrdiff_t>(first * kws::kMelBins),
                              mel.begin() + static_cast<std::ptrdiff_t>((first + kws::kEmbeddingFrames) * kws::kMelBins));
    for (float& v : window) v = v / 10.0f + 2.0f;
    const kws::Embedding full = models->embedding.embed(window);
    const kws::Embedding moved = models->embedding.embed(window, first == 0 ? 0 : 8, cache);
    float mag = 0.0f, diff = 0.0f;
    for (std::size_t d = 0; d < full.size(); ++d) {
      mag = std::max(mag, std::abs(full[d]));
      diff = std::max(diff, std::abs(full[d] - moved[d]));
    }
    worst = std::max(worst, static_cast<double>(diff / mag));
    ++windows;
  }
  CHECK(windows > 8);
  CHECK(worst < 1e-5);
}

TEST_CASE("the embedding stream gives one embedding per 80 ms, whatever the chunk sizes") {
  const std::vector<float> samples = clip_samples("marvin_en_us");
  kws::EmbeddingStream whole(shared_models());
  std::vector<kws::Embedding> a;
  CHECK(whole.push(samples, a) == samples.size() / kws::kEmbeddingHop);
  CHECK(whole.samples_seen() == static_cast<std::int64_t>(a.size()) * kws::kEmbeddingHop);
  kws::EmbeddingStream pieces(shared_models());
  std::vector<kws::Embedding> b;
  for (std::size_t at = 0; at < samples.size(); at += 333) {
    pieces.push(std::span<const float>(samples).subspan(at, std::min<std::size_t>(333, samples.size() - at)), b);
  }
  REQUIRE(a.size() == b.size());
  for (std::size_t k = 0; k < a.size(); ++k) CHECK(a[k] == b[k]);
  // Speech changes the embedding: the stream's embeddings are not all alike.
  float spread = 0.0f;
  for (std::size_t d = 0; d < kws::kEmbeddingSize; ++d) spread = std::max(spread, std::abs(a.front()[d] - a.back()[d]));
  CHECK(spread > 0.1f);
  // Skipping the first embeddings leaves the later ones as they were.
  kws::EmbeddingStream skipping(shared_models());
  skipping.skip_embeddings(5);
  std::vector<kws::Embedding> skipped;
  skipping.push(samples, skipped);
  REQUIRE(skipped.size() == a.size() - 5);
  for (std::size_t k = 0; k < skipped.size(); ++k) {
    for (std::size_t d = 0; d < kws::kEmbeddingSize; ++d) CHECK(skipped[k][d] == doctest::Approx(a[k + 5][d]).epsilon(1e-4));
  }
  pieces.reset();
  std::vector<kws::Embedding> c;
  pieces.push(samples, c);
  CHECK(c == a);
}

TEST_CASE("a missing embedding model names the file and scripts/setup") {
  const fs::path empty = fs::temp_directory_path() / "marvin-kws-no-models";
  fs::create_directories(empty);
  const std::string message = error_of([&] { kws::EmbeddingModels::load(empty); });
  CHECK(message.find((empty / "melspectrogram.onnx").string()) != std::string::npos);
  CHECK(message.find("scripts/setup") != std::string::npos);
  fs::remove_all(empty);
}

TEST_CASE("damaged ONNX files are refused with the file and byte") {
  const fs::path dir = fs::temp_directory_path() / "marvin-kws-bad-onnx";
  fs::create_directories(dir);
  std::ifstream in(kws::embedding_model_dir() / "embedding_model.onnx", std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  REQUIRE(bytes.size() > 100000);
  const fs::path truncated = dir / "truncated.onnx";
  std::ofstream(truncated, std::ios::binary) << bytes.substr(0, bytes.size() / 2);
  const std::string t = error_of([&] { kws::SpeechEmbedding e(truncated); });
  CHECK(t.find(truncated.string()) != std::string::npos);
  CHECK(t.find("at byte") != std::string::npos);
  // The mel graph is a valid ONNX file but not the embedding network.
  const std::string wrong =
      error_of([&] { kws::SpeechEmbedding e(kws::embedding_model_dir() / "melspectrogram.onnx"); });
  CHECK(wrong.find("melspectrogram.onnx: node") != std::string::npos);
  const std::string other =
      error_of([&] { kws::MelFrontEnd m(kws::embedding_model_dir() / "embedding_model.onnx"); });
  CHECK(other.find("not openWakeWord's melspectrogram") != std::string::npos);
  fs::remove_all(dir);
}
