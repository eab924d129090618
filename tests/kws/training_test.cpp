// Training: the gradient against finite differences, a tiny run that must learn a separable
// toy problem, the detection decision, and the augmentations.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>

#include "kws/training/augment.h"
#include "perception/kws/keyword_spotter.h"
#include "kws/training/trainer.h"

namespace kws = marvin::perception::kws;

namespace {

// Class c lights up a band of bins (c*10 .. c*10+9) in the middle frames, on noise.
kws::TrainingSet toy_set(int per_class, std::uint64_t seed) {
  kws::TrainingSet s;
  std::mt19937_64 rng(seed);
  std::normal_distribution<float> g(0.0f, 0.5f);
  std::uniform_int_distribution<int> shift(-4, 4);
  for (int i = 0; i < per_class * kws::kClasses; ++i) {
    const int c = i % kws::kClasses;
    const int dt = shift(rng);
    for (int t = 0; t < kws::kInputFrames; ++t) {
      for (int b = 0; b < kws::kBins; ++b) {
        float v = g(rng);
        if (t >= 10 + dt && t < 22 + dt && b / 10 == c) v += 1.5f;
        s.inputs.push_back(v);
      }
    }
    s.labels.push_back(c);
  }
  return s;
}

}  // namespace

TEST_CASE("backpropagation matches finite differences") {
  kws::FloatNetwork net = kws::make_initialised_network(3);
  for (kws::FloatLayer* l : net.layers()) {
    for (float& w : l->weights) w *= 0.5f;
    for (std::size_t i = 0; i < l->bias.size(); ++i) l->bias[i] = 0.01f * static_cast<float>(i % 7);
  }
  const kws::TrainingSet data = toy_set(1, 5);
  kws::TrainOptions o;
  o.threads = 2;
  kws::Trainer trainer(net, o);
  const std::vector<std::size_t> batch = {0, 1, 2, 3};
  kws::FloatNetwork grad;
  trainer.loss_and_gradient(data, batch, grad);
  std::mt19937_64 rng(8);
  auto layers = net.layers();
  auto glayers = grad.layers();
  int checked = 0;
  for (std::size_t li = 0; li < layers.size(); ++li) {
    for (int k = 0; k < 4; ++k) {
      const bool bias = (k == 3);
      std::vector<float>& p = bias ? layers[li]->bias : layers[li]->weights;
      const std::vector<float>& gp = bias ? glayers[li]->bias : glayers[li]->weights;
      // Pick a parameter with a gradient big enough to measure.
      std::size_t j = std::uniform_int_distribution<std::size_t>(0, p.size() - 1)(rng);
      for (std::size_t tries = 0; tries < p.size() && std::fabs(gp[j]) < 1e-4f; ++tries) j = (j + 1) % p.size();
      if (std::fabs(gp[j]) < 1e-4f) continue;
      const float saved = p[j];
      const float h = 1e-3f;
      kws::FloatNetwork scratch;
      p[j] = saved + h;
      const double up = trainer.loss_and_gradient(data, batch, scratch);
      p[j] = saved - h;
      const double down = trainer.loss_and_gradient(data, batch, scratch);
      p[j] = saved;
      const double numeric = (up - down) / (2.0 * h);
      const std::string where = "layer " + std::to_string(li) + (bias ? " bias " : " weight ") + std::to_string(j);
      INFO(where);
      CHECK(numeric == doctest::Approx(gp[j]).epsilon(0.05).scale(1e-3));
      ++checked;
    }
  }
  CHECK(checked >= 12);
}

TEST_CASE("a tiny training run learns a separable toy problem") {
  const kws::TrainingSet train = toy_set(24, 1);
  const kws::TrainingSet test = toy_set(10, 2);
  kws::FloatNetwork net = kws::make_initialised_network(4);
  const double before = kws::evaluate_float(net, test).overall;
  kws::TrainOptions o;
  o.batch_size = 16;
  o.threads = 2;
  kws::Trainer trainer(net, o);
  std::mt19937_64 rng(6);
  kws::EpochStats first, last;
  for (int e = 0; e < 4; ++e) {
    last = trainer.train_epoch(train, rng, {});
    if (e == 0) first = last;
  }
  const kws::Accuracy after = kws::evaluate_float(net, test);
  CHECK(before < 0.5);
  CHECK(last.loss < first.loss);
  CHECK(after.overall >= 0.95);
  // And the int8 version of the trained network still gets it.
  const kws::ActivationScales s = kws::calibrate(net, train, 1.0);
  CHECK(kws::evaluate_int8(kws::quantize(net, s), test).overall >= 0.95);
}

TEST_CASE("training is deterministic for a seed") {
  const kws::TrainingSet train = toy_set(4, 1);
  auto run = [&] {
    kws::FloatNetwork net = kws::make_initialised_network(12);
    kws::TrainOptions o;
    o.batch_size = 8;
    kws::Trainer trainer(net, o);
    std::mt19937_64 rng(2);
    trainer.train_epoch(train, rng, {});
    return net.dense.weights;
  };
  CHECK(run() == run());
}

TEST_CASE("spec_mask clears one band of bins and one span of frames, the same for a seed") {
  auto masked = [](int bins, int frames, std::uint64_t seed) {
    std::vector<float> x(kws::kInputSize, 1.0f);
    kws::spec_mask(x, bins, frames, seed);
    return x;
  };
  CHECK(masked(0, 0, 5) == std::vector<float>(kws::kInputSize, 1.0f));
  int widest_band = 0, widest_span = 0;
  for (std::uint64_t seed = 0; seed < 200; ++seed) {
    const std::vector<float> x = masked(6, 4, seed);
    CHECK(x == masked(6, 4, seed));
    // Cleared bins are zero in every frame, cleared frames in every bin; all else is 1.
    std::vector<bool> bin_cleared(kws::kBins, true), frame_cleared(kws::kInputFrames, true);
    int changed = 0;  // values other than 0 (cleared) and 1 (kept)
    for (int t = 0; t < kws::kInputFrames; ++t) {
      for (int b = 0; b < kws::kBins; ++b) {
        const float v = x[static_cast<std::size_t>(t * kws::kBins + b)];
        if (v != 0.0f && v != 1.0f) ++changed;
        if (v != 0.0f) {
          bin_cleared[static_cast<std::size_t>(b)] = false;
          frame_cleared[static_cast<std::size_t>(t)] = false;
        }
      }
    }
    CHECK(changed == 0);
    int band = 0, span = 0;
    for (bool c : bin_cleared) band += c ? 1 : 0;
    for (bool c : frame_cleared) span += c ? 1 : 0;
    int zeros = 0;
    for (float v : x) zeros += v == 0.0f ? 1 : 0;
    CHECK(zeros == band * kws::kInputFrames + span * kws::kBins - band * span);
    CHECK(band <= 6);
    CHECK(span <= 4);
    widest_band = std::max(widest_band, band);
    widest_span = std::max(widest_span, span);
  }
  CHECK(widest_band == 6);
  CHECK(widest_span == 4);
}

TEST_CASE("warp_frequency moves a formant by the factor and keeps factor 1 as it is") {
  // Centre frequency of each bin, computed here from the HTK mel formula (20 Hz..8 kHz).
  auto mel = [](double hz) { return 2595.0 * std::log10(1.0 + hz / 700.0); };
  auto centre_hz = [&](int i) {
    const double m = mel(20.0) + (mel(8000.0) - mel(20.0)) * (i + 1) / (kws::kBins + 1);
    return 700.0 * (std::pow(10.0, m / 2595.0) - 1.0);
  };
  auto with_peak_at = [](int bin) {
    std::vector<float> x(kws::kInputSize, 0.0f);
    for (int t = 0; t < kws::kInputFrames; ++t) x[static_cast<std::size_t>(t * kws::kBins + bin)] = 1.0f;
    return x;
  };
  auto peak_bin = [](const std::vector<float>& x, int frame) {
    const auto row = x.begin() + frame * kws::kBins;
    return static_cast<int>(std::max_element(row, row + kws::kBins) - row);
  };
  std::vector<float> ramp(kws::kInputSize);
  for (std::size_t i = 0; i < ramp.size(); ++i) ramp[i] = static_cast<float>(i % kws::kBins);
  std::vector<float> same = ramp;
  kws::warp_frequency(same, 1.0f);
  for (std::size_t i = 0; i < ramp.size(); ++i) REQUIRE(same[i] == doctest::Approx(ramp[i]).epsilon(1e-4));

  for (const float factor : {0.8f, 1.25f, 1.4f}) {
    const int from = 18;
    std::vector<float> x = with_peak_at(from);
    kws::warp_frequency(x, factor);
    int expected = 0;  // the bin whose centre is nearest to factor x the peak's frequency
    for (int i = 1; i < kws::kBins; ++i) {
      if (std::fabs(centre_hz(i) - factor * centre_hz(from)) <
          std::fabs(centre_hz(expected) - factor * centre_hz(from))) {
        expected = i;
      }
    }
    CAPTURE(factor);
    CHECK(expected != from);
    CHECK(std::abs(peak_bin(x, 0) - expected) <= 1);
    CHECK(peak_bin(x, kws::kInputFrames - 1) == peak_bin(x, 0));  // every frame alike
  }
  // Lowering the formants reads above the top bin for the top bins: they hold its value.
  std::vector<float> top = with_peak_at(kws::kBins - 1);
  kws::warp_frequency(top, 0.8f);
  CHECK(top[kws::kBins - 1] == 1.0f);
  CHECK(top[0] == 0.0f);
}

TEST_CASE("training with masking or warping repeats for a seed and differs from training without") {
  const kws::TrainingSet train = toy_set(4, 1);
  const kws::FloatNetwork initial = kws::make_initialised_network(12);
  auto run = [&](int bins, int frames, float warp = 0.0f) {
    kws::FloatNetwork net = initial;
    kws::TrainOptions o;
    o.batch_size = 8;
    o.freq_mask_bins = bins;
    o.time_mask_frames = frames;
    o.freq_warp = warp;
    kws::Trainer trainer(net, o);
    std::mt19937_64 rng(2);
    trainer.train_epoch(train, rng, {});
    return net.dense.weights;
  };
  // Largest difference between two runs' weights, relative to how far training moved them.
  // Runs with one seed agree up to float rounding only: Eigen's vectorised sums group terms
  // by where the weights happen to sit in memory (their alignment), which differs between
  // allocations.
  auto relative_difference = [&](const std::vector<float>& a, const std::vector<float>& b) {
    float diff = 0.0f, moved = 0.0f;
    for (std::size_t i = 0; i < a.size(); ++i) {
      diff = std::max(diff, std::fabs(a[i] - b[i]));
      moved = std::max(moved, std::fabs(a[i] - initial.dense.weights[i]));
    }
    return diff / moved;
  };
  const std::vector<float> masked = run(6, 4);
  CHECK(relative_difference(masked, run(6, 4)) < 1e-3f);
  CHECK(relative_difference(masked, run(0, 0)) > 0.05f);
  const std::vector<float> warped = run(0, 0, 0.3f);
  CHECK(relative_difference(warped, run(0, 0, 0.3f)) < 1e-3f);
  CHECK(relative_difference(warped, run(0, 0)) > 0.05f);
}

TEST_CASE("detection decision: smoothing, threshold, one detection per keyword") {
  kws::DetectionDecider d(3, 0.6f, 4);
  // A keyword seen by four overlapping windows fires once.
  const float posteriors[] = {0.0f, 0.1f, 0.9f, 0.95f, 0.9f, 0.8f, 0.1f, 0.0f, 0.0f, 0.0f};
  int fired = 0, fired_at = -1;
  for (int i = 0; i < 10; ++i) {
    if (d.push(posteriors[i])) {
      ++fired;
      fired_at = i;
    }
  }
  CHECK(fired == 1);
  CHECK(fired_at == 3);  // (0 + 0.1 + 0.9) / 3 < 0.6 at i = 2; (0.1 + 0.9 + 0.95) / 3 >= 0.6 at i = 3
  // One lone high window is smoothed away.
  d.reset();
  CHECK_FALSE(d.push(0.0f));
  CHECK_FALSE(d.push(1.0f));
  CHECK_FALSE(d.push(0.0f));
  // Two keywords further apart than the refractory period fire twice.
  d.reset();
  fired = 0;
  for (int i = 0; i < 20; ++i) fired += d.push(i % 10 < 4 ? 1.0f : 0.0f) ? 1 : 0;
  CHECK(fired == 2);
}

TEST_CASE("augmentations keep their promises") {
  std::mt19937_64 rng(1);
  // A 300 Hz tone, 1 s.
  std::vector<float> tone(16000);
  for (std::size_t i = 0; i < tone.size(); ++i) tone[i] = 0.5f * std::sin(2.0f * 3.14159265f * 300.0f * static_cast<float>(i) / 16000.0f);
  auto zero_crossings = [](const std::vector<float>& x) {
    int n = 0;
    for (std::size_t i = 1; i < x.size(); ++i) n += (x[i - 1] < 0.0f) != (x[i] < 0.0f) ? 1 : 0;
    return n;
  };
  const std::vector<float> slow = kws::time_stretch(tone, 0.8);  // longer, same pitch
  CHECK(slow.size() == 20000);
  CHECK(zero_crossings(slow) / (static_cast<double>(slow.size()) / 16000.0) == doctest::Approx(600.0).epsilon(0.05));
  const std::vector<float> up = kws::shift_pitch(tone, 12.0);  // an octave up, same length
  CHECK(static_cast<double>(up.size()) == doctest::Approx(16000.0).epsilon(0.01));
  CHECK(zero_crossings(up) / (static_cast<double>(up.size()) / 16000.0) == doctest::Approx(1200.0).epsilon(0.05));
  const std::vector<float> both = kws::change_speed_and_pitch(tone, 1.25);
  CHECK(static_cast<double>(both.size()) == doctest::Approx(12800.0).epsilon(0.01));
  // Harmonic + percussive with gains 1 and 1 gives the signal back.
  const std::vector<float> same = kws::hpss_remix(tone, 1.0f, 1.0f);
  double err = 0.0;
  for (std::size_t i = 1000; i < 15000; ++i) err = std::max(err, static_cast<double>(std::fabs(same[i] - tone[i])));
  CHECK(err < 1e-3);
  // A steady tone is harmonic: dropping the percussive part keeps most of it.
  const std::vector<float> harmonic = kws::hpss_remix(tone, 1.0f, 0.0f);
  CHECK(kws::rms(std::span<const float>(harmonic).subspan(2000, 12000)) > 0.9f * kws::rms(tone));
  // Noise at a given SNR.
  std::vector<float> x = tone;
  const std::vector<float> n = kws::make_noise(kws::NoiseColour::pink, 16000, 0.1f, rng);
  kws::add_noise_at_snr(x, n, 0.0f, rng);
  std::vector<float> diff(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) diff[i] = x[i] - tone[i];
  CHECK(kws::rms(diff) == doctest::Approx(kws::rms(tone)).epsilon(0.05));
}

TEST_CASE("reverb spreads a click into a decaying tail and keeps length and peak") {
  std::vector<float> click(16000, 0.0f);
  click[100] = 0.5f;
  std::mt19937_64 rng(3);
  const std::vector<float> wet = kws::add_reverb(click, 0.4f, -6.0f, rng);
  REQUIRE(wet.size() == click.size());
  float peak = 0.0f;
  for (float v : wet) peak = std::max(peak, std::fabs(v));
  CHECK(peak == doctest::Approx(0.5f).epsilon(1e-4));
  CHECK(wet[100] == doctest::Approx(0.5f).epsilon(1e-4));  // the direct path stays the peak
  for (std::size_t i = 0; i < 100; ++i) CHECK(wet[i] == 0.0f);  // nothing before the sound
  // The tail: energy right after the click, less 200 ms later, next to none past the RT60.
  auto energy = [&](std::size_t from, std::size_t n) {
    return kws::rms(std::span<const float>(wet).subspan(from, n));
  };
  const float early = energy(101 + 160, 1600), late = energy(101 + 3200, 1600);
  CHECK(early > 0.0f);
  CHECK(late < 0.5f * early);
  CHECK(energy(101 + 6600, 1600) < 0.01f * early);
  // The same seed gives the same room.
  std::mt19937_64 again(3);
  CHECK(kws::add_reverb(click, 0.4f, -6.0f, again) == wet);
}

TEST_CASE("band_limit passes speech frequencies and cuts below and above its corners") {
  auto tone = [](float hz) {
    std::vector<float> x(16000);
    for (std::size_t i = 0; i < x.size(); ++i)
      x[i] = 0.5f * std::sin(2.0f * 3.14159265f * hz * static_cast<float>(i) / 16000.0f);
    return x;
  };
  auto gain = [&](float hz) {
    std::vector<float> x = tone(hz);
    const float before = kws::rms(std::span<const float>(x).subspan(4000, 12000));
    kws::band_limit(x, 200.0f, 4000.0f);
    return kws::rms(std::span<const float>(x).subspan(4000, 12000)) / before;
  };
  CHECK(gain(1000.0f) == doctest::Approx(1.0f).epsilon(0.05));
  CHECK(gain(200.0f) == doctest::Approx(0.707f).epsilon(0.05));  // -3 dB at the corner
  CHECK(gain(50.0f) < 0.1f);                                      // 12 dB per octave
  CHECK(gain(7500.0f) < 0.35f);
}

TEST_CASE("drop_out silences 50..300 ms stretches after `from` and nothing else") {
  std::vector<float> tone(32000);
  for (std::size_t i = 0; i < tone.size(); ++i)
    tone[i] = 0.5f * std::sin(0.1f * static_cast<float>(i)) + 0.6f;  // never zero
  int longest = 0, shortest = 1 << 30;
  for (std::uint64_t seed = 1; seed <= 40; ++seed) {
    CAPTURE(seed);
    std::vector<float> x = tone;
    std::mt19937_64 rng(seed);
    const std::size_t changed = kws::drop_out(x, 12000, 1, rng);
    std::size_t begin = x.size(), end = 0, altered = 0, zeros = 0;
    for (std::size_t i = 0; i < x.size(); ++i) {
      if (x[i] == 0.0f) {
        begin = std::min(begin, i);
        end = i + 1;
        ++zeros;
      } else {
        altered += x[i] != tone[i] ? 1 : 0;
      }
    }
    CHECK(altered == 0);
    REQUIRE(end > begin);
    CHECK(begin >= 12000);
    CHECK(changed == end - begin);
    CHECK(zeros == end - begin);  // one stretch
    const int length = static_cast<int>(end - begin);
    if (end < x.size()) {  // not cut short by the end of the sound
      CHECK(length >= 800);
      shortest = std::min(shortest, length);
    }
    CHECK(length <= 4800);
    longest = std::max(longest, length);
    std::vector<float> again = tone;
    std::mt19937_64 rng2(seed);
    kws::drop_out(again, 12000, 1, rng2);
    CHECK(again == x);
  }
  CHECK(longest > 3000);  // the lengths spread over the range
  CHECK(shortest < 2000);
  std::vector<float> short_sound(100, 1.0f);
  std::mt19937_64 rng(1);
  CHECK(kws::drop_out(short_sound, 100, 2, rng) == 0);  // nothing after `from`
  CHECK(short_sound == std::vector<float>(100, 1.0f));
}
