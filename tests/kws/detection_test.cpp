// The shipped model on speech made by espeak-ng during the test: a spoken "marvin" fires
// once, ordinary sentences never; the audio and feature entry points agree.
#include <doctest/doctest.h>

#include <cstdlib>
#include <filesystem>

#include "devices/audio/sound_buffer.h"
#include "kws/training/dataset.h"
#include "perception/kws/neural_wake_word.h"
#include "perception/log_mel.h"
#include "kws/spoken_clip.h"

namespace kws = marvin::perception::kws;
namespace perception = marvin::perception;

namespace {

std::filesystem::path shipped_model() {
  const char* src = std::getenv("MARVIN_SOURCE_DIR");
  return std::filesystem::path(src ? src : MARVIN_TEST_SOURCE_DIR) / "models" / "marvin-kws.bin";
}

const kws::KwsModel& model() {
  static const kws::KwsModel m = kws::load_model(shipped_model());
  return m;
}

// Speech with a second of quiet on both sides.
std::vector<std::int16_t> spoken(const std::string& text, const std::string& voice) {
  return kws::testing::spoken_clip(text, voice, 16000);
}

std::size_t detections_in(const std::vector<std::int16_t>& pcm, std::vector<perception::WakeWordDetection>* out = nullptr) {
  kws::NeuralWakeWord detector(model(), 0.5f, kws::Precision::int8);
  std::vector<perception::WakeWordDetection> det;
  // In 100 ms chunks, as the microphone delivers them.
  for (std::size_t i = 0; i < pcm.size(); i += 1600) {
    detector.process(std::span<const std::int16_t>(pcm).subspan(i, std::min<std::size_t>(1600, pcm.size() - i)), det);
  }
  if (out) *out = det;
  return det.size();
}

}  // namespace

TEST_CASE("the shipped model loads and is small") {
  CHECK(std::filesystem::file_size(shipped_model()) < 300 * 1024);
  CHECK(model().keyword == "marvin");
  CHECK(model().quantized.has_value());
}

TEST_CASE("a synthesised \"marvin\" is detected once") {
  for (const char* voice : {"en-us", "en-gb-x-gbclan+m7"}) {  // a training and a held-out voice
    INFO("voice " << std::string(voice));
    const std::vector<std::int16_t> pcm = spoken("Marvin", voice);
    std::vector<perception::WakeWordDetection> det;
    CHECK(detections_in(pcm, &det) == 1);
    if (!det.empty()) {
      // It fires around the word: the window holding the word ends after it started.
      CHECK(det[0].end_sample > 16000);
      CHECK(det[0].begin_sample < static_cast<std::int64_t>(pcm.size()) - 16000);
      CHECK(det[0].score >= kws::NeuralWakeWord(model(), 0.5f, kws::Precision::int8).threshold_for(0.5f));
    }
  }
}

TEST_CASE("every int8 kernel the CPU has gives the same detections; a float spotter has none") {
  const std::vector<std::int16_t> pcm = spoken("Marvin", "en-us");
  std::vector<std::vector<perception::WakeWordDetection>> seen;
  for (kws::Int8Kernel k :
       {kws::Int8Kernel::portable, kws::Int8Kernel::avx2, kws::Int8Kernel::avx512_vnni}) {
    if (!kws::kernel_available(k)) continue;
    INFO("kernel " << kws::kernel_name(k));
    kws::NeuralWakeWord detector(model(), 0.5f, kws::Precision::int8);
    detector.spotter().set_int8_kernel(k);
    std::vector<perception::WakeWordDetection> det;
    for (std::size_t i = 0; i < pcm.size(); i += 1600) {
      detector.process(std::span<const std::int16_t>(pcm).subspan(
                           i, std::min<std::size_t>(1600, pcm.size() - i)),
                       det);
    }
    REQUIRE(det.size() == 1);
    if (!seen.empty()) {
      CHECK(det[0].end_sample == seen[0][0].end_sample);
      CHECK(det[0].score == seen[0][0].score);
    }
    seen.push_back(det);
  }
  kws::NeuralWakeWord float_detector(model(), 0.5f, kws::Precision::float32);
  CHECK_THROWS_WITH_AS(float_detector.spotter().set_int8_kernel(kws::Int8Kernel::portable),
                       doctest::Contains("this spotter runs in float"), std::logic_error);
}

TEST_CASE("sentences without the keyword are not detected") {
  CHECK(detections_in(spoken("please turn on the lights in the kitchen", "en-us")) == 0);
  CHECK(detections_in(spoken("what time is it", "en-gb-x-gbcwmd+f5")) == 0);
}

TEST_CASE("process() and process_features() give the same detections") {
  const std::vector<std::int16_t> pcm = spoken("Marvin", "en-us");
  kws::NeuralWakeWord a(model(), 0.5f, kws::Precision::int8);
  kws::NeuralWakeWord b(model(), 0.5f, kws::Precision::int8);
  CHECK(a.wants_features());
  std::vector<perception::WakeWordDetection> da, db;
  a.process(pcm, da);
  perception::LogMelExtractor extractor;
  std::int64_t frame = 0;
  extractor.push(pcm, [&](std::span<const float> bins) { b.process_features(bins, frame++, db); });
  REQUIRE(da.size() == db.size());
  for (std::size_t i = 0; i < da.size(); ++i) {
    CHECK(da[i].end_sample == db[i].end_sample);
    CHECK(da[i].score == db[i].score);
  }
  // After reset() the same audio gives the same answer again.
  a.reset();
  std::vector<perception::WakeWordDetection> again;
  a.process(pcm, again);
  CHECK(again.size() == da.size());
}

TEST_CASE("sensitivity maps to the threshold, clamped") {
  kws::NeuralWakeWord d(model(), 0.5f, kws::Precision::int8);
  CHECK(d.threshold_for(0.5f) == doctest::Approx(model().detection.threshold));
  CHECK(d.threshold_for(0.0f) == doctest::Approx(0.99f));
  CHECK(d.threshold_for(1.0f) == doctest::Approx(0.05f));
  d.set_sensitivity(7.0f);
  CHECK(d.sensitivity() == 1.0f);
  CHECK(d.spotter().threshold() == doctest::Approx(0.05f));
}

TEST_CASE("a missing model file is a clear error") {
  kws::NeuralWakeWordOptions o;
  o.model_path = "/nonexistent/kws.bin";
  CHECK_THROWS_WITH_AS(kws::NeuralWakeWord{o}, doctest::Contains("/nonexistent/kws.bin: cannot open"),
                       kws::ModelFileError);
}
