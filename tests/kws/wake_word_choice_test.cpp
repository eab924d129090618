// The host's choice of wake word (app::make_wake_word): the embedding detector when its
// models are there, the cnn spotter with a warning naming the missing file and scripts/setup
// when they are not, and a clear error for an unknown name.
#include <doctest/doctest.h>

#include <cstdlib>
#include <filesystem>
#include <mutex>
#include <string>

#include "app/voice_host.h"
#include "common/log.h"
#include "perception/kws/embedding_wake_word.h"
#include "perception/kws/neural_wake_word.h"

namespace {

struct EnvGuard {
  explicit EnvGuard(const char* value) { setenv("MARVIN_KWS_EMBEDDING_DIR", value, 1); }
  ~EnvGuard() { unsetenv("MARVIN_KWS_EMBEDDING_DIR"); }
};

}  // namespace

TEST_CASE("--wake-word embedding falls back to the cnn spotter when setup has not run") {
  const auto empty = std::filesystem::temp_directory_path() / "marvin-no-kws-models";
  std::filesystem::create_directories(empty);
  std::mutex m;
  std::string warnings;
  const auto old = marvin::set_log_sink([&](marvin::LogLevel level, std::string_view, std::string_view msg) {
    std::lock_guard<std::mutex> lock(m);
    if (level == marvin::LogLevel::kWarning) warnings += std::string(msg) + "\n";
  });
  {
    EnvGuard env(empty.c_str());
    auto detector = marvin::app::make_wake_word("embedding", 0.5f);
    CHECK(dynamic_cast<marvin::perception::kws::NeuralWakeWord*>(detector.get()) != nullptr);
    CHECK(detector->keyword() == "marvin");
  }
  marvin::set_log_sink(old);
  CHECK(warnings.find((empty / "melspectrogram.onnx").string()) != std::string::npos);
  CHECK(warnings.find("scripts/setup") != std::string::npos);
  std::filesystem::remove_all(empty);
}

TEST_CASE("--wake-word embedding uses the embedding detector when its models are there") {
  auto detector = marvin::app::make_wake_word("embedding", 0.5f);
  CHECK(dynamic_cast<marvin::perception::kws::EmbeddingWakeWord*>(detector.get()) != nullptr);
  CHECK(detector->keyword() == "marvin");
  CHECK(dynamic_cast<marvin::perception::kws::NeuralWakeWord*>(marvin::app::make_wake_word("cnn", 0.5f).get()) != nullptr);
  CHECK_THROWS_WITH(marvin::app::make_wake_word("snowboy", 0.5f),
                    doctest::Contains("expected embedding, cnn (or neural) or pocketsphinx"));
}

TEST_CASE("the host listens with the embedding wake word unless told otherwise") {
  const marvin::app::VoiceHostOptions defaults;
  auto detector = marvin::app::make_wake_word(defaults.wake_word, defaults.sensitivity);
  CHECK(dynamic_cast<marvin::perception::kws::EmbeddingWakeWord*>(detector.get()) != nullptr);
}
