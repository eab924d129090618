// The embedding wake word with the shipped head (models/marvin-embedding-head.bin) on speech
// made by espeak-ng during the test: a spoken "marvin" fires once, an ordinary sentence never.
#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>

#include "devices/audio/sound_buffer.h"
#include "kws/training/dataset.h"
#include "perception/kws/embedding_wake_word.h"
#include "kws/spoken_clip.h"

namespace kws = marvin::perception::kws;
namespace perception = marvin::perception;

namespace {

const kws::EmbeddingHead& shipped_head() {
  static const kws::EmbeddingHead h =
      kws::load_head(std::filesystem::path(MARVIN_TEST_SOURCE_DIR) / "models/marvin-embedding-head.bin");
  return h;
}

std::shared_ptr<const kws::EmbeddingModels> front_end() {
  static const auto m = kws::EmbeddingModels::load();
  return m;
}

// Speech with a second of quiet before and 1.5 s after, over faint noise.
std::vector<std::int16_t> spoken_with_pauses(const std::string& text, const std::string& voice) {
  return kws::testing::spoken_clip(text, voice, 24000, 1e-3f);
}

std::vector<perception::WakeWordDetection> detections(const std::vector<std::int16_t>& pcm) {
  kws::EmbeddingWakeWord detector(front_end(), shipped_head(), 0.5f);
  std::vector<perception::WakeWordDetection> det;
  for (std::size_t i = 0; i < pcm.size(); i += 1600) {
    detector.process(std::span<const std::int16_t>(pcm).subspan(i, std::min<std::size_t>(1600, pcm.size() - i)), det);
  }
  return det;
}

}  // namespace

TEST_CASE("the shipped embedding head is small and for \"marvin\"") {
  // Five heads of 32 hidden units merged into one (1.04 MiB); the cap catches a head far bigger
  // than that by mistake (1024 hidden units would be 10 MiB).
  CHECK(std::filesystem::file_size(std::filesystem::path(MARVIN_TEST_SOURCE_DIR) /
                                   "models/marvin-embedding-head.bin") < 1280 * 1024);
  CHECK(shipped_head().keyword == "marvin");
}

TEST_CASE("a synthesised \"marvin\" is detected once by the embedding wake word") {
  for (const char* voice : {"en-us", "en-gb-x-gbclan+m7"}) {  // a training and a held-out voice
    INFO("voice " << std::string(voice));
    const std::vector<std::int16_t> pcm = spoken_with_pauses("Marvin", voice);
    const auto det = detections(pcm);
    CHECK(det.size() == 1);
    if (!det.empty()) {
      CHECK(det[0].end_sample > 16000);
      CHECK(det[0].score >= shipped_head().threshold);
    }
  }
}

TEST_CASE("\"hey marvin\" in one breath is detected once by the embedding wake word") {
  // People call the robot with a word before its name as often as by the name alone; the head
  // learnt it from lead-ins (marvin-kws-train --lead-ins). The head before it heard none of
  // these four. Not every lead-in and voice is heard: on held-out voices about three in four
  // (models/README.md, "Session 18"; "Okay Marvin" in en-us is one it misses).
  for (const char* voice : {"en-us", "en-gb-x-gbclan+m7"}) {
    for (const char* text : {"Hey Marvin", "Excuse me Marvin"}) {
      INFO("voice " << std::string(voice) << ": " << std::string(text));
      CHECK(detections(spoken_with_pauses(text, voice)).size() == 1);
    }
  }
}

TEST_CASE("a sentence without the keyword is not detected by the embedding wake word") {
  CHECK(detections(spoken_with_pauses("please turn on the lights in the kitchen", "en-us")).empty());
  CHECK(detections(spoken_with_pauses("what time is it", "en-gb-x-gbcwmd+f5")).empty());
}

TEST_CASE("embedding wake word: sensitivity maps to the threshold, reset repeats the answer") {
  kws::EmbeddingWakeWord d(front_end(), shipped_head(), 0.5f);
  CHECK(d.threshold_for(0.5f) == doctest::Approx(shipped_head().threshold));
  CHECK(d.threshold_for(0.0f) == doctest::Approx(0.99f));
  CHECK(d.threshold_for(1.0f) == doctest::Approx(0.05f));
  d.set_sensitivity(-3.0f);
  CHECK(d.sensitivity() == 0.0f);
  const std::vector<std::int16_t> pcm = spoken_with_pauses("Marvin", "en-us");
  d.set_sensitivity(0.5f);
  std::vector<perception::WakeWordDetection> a, b;
  d.process(pcm, a);
  d.reset();
  d.process(pcm, b);
  REQUIRE(a.size() == b.size());
  for (std::size_t k = 0; k < a.size(); ++k) CHECK(a[k].end_sample == b[k].end_sample);
}

TEST_CASE("a head that needs N consecutive scores fires on the N-th step over the threshold") {
  // All weights zero and b3 = 5: every score is sigmoid(5) = 0.993, from the 16th embedding on.
  kws::EmbeddingHead always;
  always.resize(4);
  always.b3 = 5.0f;
  always.threshold = 0.9f;
  always.refractory_seconds = 100.0f;  // one detection per run
  const std::vector<float> quiet(16000 * 3, 0.0f);
  std::int64_t first_end[2] = {0, 0};
  for (int n : {1, 3}) {
    always.consecutive = n;
    kws::EmbeddingWakeWord d(front_end(), always, 0.5f);
    std::vector<perception::WakeWordDetection> det;
    d.process_float(quiet, det);
    REQUIRE(det.size() == 1);
    first_end[n == 1 ? 0 : 1] = det[0].end_sample;
  }
  // Two 80 ms steps (1280 samples each) later with 3 steps than with 1.
  CHECK(first_end[1] - first_end[0] == 2 * kws::kEmbeddingHop);
}

TEST_CASE(
    "a stricter sensitivity fires later but places the keyword's end where the default does") {
  // Where the command starts must not move into it when Marvin needs to be surer of his name
  // (embedding_wake_word.h, "Where the keyword ended"). This voice scores over 0.8 some steps
  // before it scores over 0.971 (sensitivity 0.05); most reach both at once.
  const std::vector<std::int16_t> pcm =
      spoken_with_pauses("Marvin, what time is it", "en-gb-x-gbclan+m7");
  std::int64_t end[2] = {-1, -1};
  std::size_t fired[2] = {0, 0};
  const float sensitivities[2] = {0.5f, 0.05f};
  for (int k = 0; k < 2; ++k) {
    kws::EmbeddingWakeWord d(front_end(), shipped_head(), sensitivities[k]);
    std::vector<perception::WakeWordDetection> det;
    for (std::size_t i = 0; i < pcm.size() && det.empty(); i += 160) {
      d.process(
          std::span<const std::int16_t>(pcm).subspan(i, std::min<std::size_t>(160, pcm.size() - i)),
          det);
      fired[k] = i + 160;
    }
    REQUIRE(det.size() == 1);
    end[k] = det[0].end_sample;
  }
  CHECK(fired[1] > fired[0]);  // surer takes longer ...
  CHECK(end[1] == end[0]);     // ... but the word ended where it ended
  CHECK(end[0] <= static_cast<std::int64_t>(fired[0]));
}
