// Hard-negative mining inputs: the keyword-free speech the trainer mines (words, sentences,
// audio) and the streaming windows cut from it, which must be exactly what KeywordSpotter
// sees, or the mined examples would teach the network about windows it never meets.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>

#include "devices/audio/sound_buffer.h"
#include "kws/training/augment.h"
#include "kws/training/dataset.h"
#include "perception/kws/keyword_spotter.h"
#include "perception/kws/neural_wake_word.h"

namespace kws = marvin::perception::kws;

TEST_CASE("confusable words and varied sentences never contain the keyword") {
  CHECK(kws::confusable_words().size() >= 40);
  for (const std::string& w : kws::confusable_words()) {
    INFO(w);
    CHECK(w.find("marvin") == std::string::npos);
  }
  std::mt19937_64 a(5), b(5);
  int with_confusable = 0;
  for (int i = 0; i < 500; ++i) {
    const std::string s = kws::varied_sentence(a);
    CHECK(s == kws::varied_sentence(b));  // deterministic for a seed
    CHECK(s.find("marvin") == std::string::npos);
    CHECK(s.find("Marvin") == std::string::npos);
    for (const std::string& w : kws::confusable_words()) {
      if (s.find(w) != std::string::npos && w.size() > 4) {
        ++with_confusable;
        break;
      }
    }
  }
  // About one word in five is confusable, so most sentences hold one.
  CHECK(with_confusable > 250);
}

TEST_CASE("lead-in words are neither the keyword nor a piece of it") {
  REQUIRE(kws::lead_in_words().size() >= 8);
  for (const std::string& w : kws::lead_in_words()) {
    INFO(w);
    // "hey marvin" must be the keyword after a lead-in, never a longer word that holds it.
    CHECK(w.find("mar") == std::string::npos);
    CHECK(w.find("vin") == std::string::npos);
    CHECK(std::count(kws::lead_in_words().begin(), kws::lead_in_words().end(), w) == 1);
  }
}

// Not compared sample by sample across two calls: espeak-ng's output depends on the engine's
// state from earlier calls in the process (a fresh process with the same calls repeats
// itself, which is what makes a training run reproducible).
TEST_CASE("negative speech: the length asked for, speech over noise") {
  const std::vector<std::string> voices = {"en-us", "en+f2"};
  std::mt19937_64 noise_rng(3);
  const std::vector<std::vector<float>> pool = {
      kws::make_noise(kws::NoiseColour::pink, 32000, 0.1f, noise_rng)};
  std::mt19937_64 r1(9), r2(9);
  const std::vector<float> a = kws::negative_speech(6.0, voices, pool, r1);
  const std::vector<float> b = kws::negative_speech(6.0, voices, pool, r2);
  REQUIRE(a.size() == 6 * 16000);
  CHECK(b.size() == a.size());
  float peak = 0.0f;
  for (float v : a) peak = std::max(peak, std::fabs(v));
  CHECK(peak <= 1.0f);
  CHECK(peak > 0.1f);  // speech at -18..-4 dB peak, not just the -50..-35 dBFS background
  // The background never stops: the quietest 100 ms is not digital silence.
  float quietest = 1.0f;
  for (std::size_t i = 0; i + 1600 <= a.size(); i += 1600) {
    quietest = std::min(quietest, kws::rms(std::span<const float>(a).subspan(i, 1600)));
  }
  CHECK(quietest > 1e-4f);
  std::mt19937_64 r3(9);
  CHECK(kws::negative_speech(0.0, voices, pool, r3).empty());
}

TEST_CASE("stream windows are the windows the streaming spotter classifies") {
  // A random float network: the check is that inputs agree, not what they mean.
  kws::KwsModel model;
  model.network = kws::make_initialised_network(7);
  for (std::size_t b = 0; b < model.normalisation.mean.size(); ++b) {
    model.normalisation.mean[b] = -5.0f + 0.1f * static_cast<float>(b);
  }
  model.normalisation.inv_std = 0.4f;
  std::mt19937_64 rng(11);
  std::vector<float> audio =
      kws::synthesize("the garden looks lovely after the rain", "en-us", 150, 50);
  audio.resize(3 * 16000 + 1234, 0.0f);
  const std::vector<float> floor =
      kws::make_noise(kws::NoiseColour::white, audio.size(), 0.01f, rng);
  for (std::size_t i = 0; i < audio.size(); ++i)
    audio[i] = std::clamp(audio[i] * 0.5f + floor[i], -1.0f, 1.0f);

  kws::TrainingSet windows = kws::stream_windows(audio, model.features.hop_frames, 1);
  // Frames: 1 + (samples - 400) / 160; a window after 96 of them, then every 25.
  const std::size_t frames = 1 + (audio.size() - 400) / 160;
  REQUIRE(windows.size() == 1 + (frames - kws::kWindowFrames) / 25);
  for (int label : windows.labels) CHECK(label == 1);
  kws::normalise(windows, model.normalisation);

  struct Seen {
    std::vector<float> posteriors;
  } seen;
  kws::NeuralWakeWord detector(model, 0.5f, kws::Precision::float32);
  detector.spotter().set_window_observer(
      [](void* ctx, std::int64_t, float posterior, float) {
        static_cast<Seen*>(ctx)->posteriors.push_back(posterior);
      },
      &seen);
  std::vector<std::int16_t> pcm(audio.size());
  marvin::audio::float_to_pcm16(audio, pcm);
  std::vector<marvin::perception::WakeWordDetection> det;
  for (std::size_t i = 0; i < pcm.size(); i += 1600) {
    detector.process(
        std::span<const std::int16_t>(pcm).subspan(i, std::min<std::size_t>(1600, pcm.size() - i)),
        det);
  }
  REQUIRE(seen.posteriors.size() == windows.size());
  kws::FloatInference net(model.network);
  float probs[kws::kClasses];
  for (std::size_t i = 0; i < windows.size(); ++i) {
    net.run(windows.input(i), probs);
    CHECK(probs[0] == doctest::Approx(seen.posteriors[i]).epsilon(1e-5));
  }
}
