// Log-mel features against an independent reference: a direct DFT (double precision) of a
// Hamming-windowed known tone, with the mel filters rebuilt here from their definition.
#include <doctest/doctest.h>

#include <cmath>
#include <complex>
#include <cstdint>
#include <cstdlib>
#include <new>
#include <numbers>
#include <random>
#include <vector>

#include "perception/fft.h"
#include "perception/log_mel.h"

namespace {

// Counts every allocation in this test program, to check the steady state allocates nothing.
std::size_t g_allocations = 0;

}  // namespace

void* operator new(std::size_t size) {
  ++g_allocations;
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}
// The nothrow form too (std::stable_sort's temporary buffer uses it): every new of this
// program must come from malloc, as every delete here goes to free.
void* operator new(std::size_t size, const std::nothrow_t&) noexcept {
  ++g_allocations;
  return std::malloc(size == 0 ? 1 : size);
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { std::free(p); }

namespace {

using marvin::perception::LogMelExtractor;
using marvin::perception::LogMelOptions;

std::vector<float> tone(double hz, double amplitude, int samples, int rate = 16000) {
  std::vector<float> out(static_cast<std::size_t>(samples));
  for (int n = 0; n < samples; ++n) {
    out[static_cast<std::size_t>(n)] =
        static_cast<float>(amplitude * std::sin(2.0 * std::numbers::pi * hz * n / rate));
  }
  return out;
}

// The reference: everything in double, DFT by definition, filters from the mel formula.
std::vector<double> reference_log_mel(const std::vector<float>& frame, const LogMelOptions& o) {
  const std::size_t n = frame.size();
  const std::size_t nfft = static_cast<std::size_t>(o.fft_size);
  double mean = 0;
  for (float s : frame) mean += s;
  mean /= static_cast<double>(n);
  std::vector<double> x(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double hamming = 0.54 - 0.46 * std::cos(2 * std::numbers::pi * static_cast<double>(i) /
                                                  static_cast<double>(n - 1));
    x[i] = (frame[i] - mean) * hamming;
  }
  std::vector<double> power(nfft / 2 + 1);
  for (std::size_t k = 0; k < power.size(); ++k) {
    std::complex<double> sum = 0;
    for (std::size_t i = 0; i < n; ++i) {
      sum += x[i] * std::polar(1.0, -2 * std::numbers::pi * static_cast<double>(k * i) /
                                        static_cast<double>(nfft));
    }
    power[k] = std::norm(sum);
  }
  auto mel = [](double hz) { return 1127.0 * std::log(1.0 + hz / 700.0); };  // = 2595 log10
  auto hz = [](double m) { return 700.0 * (std::exp(m / 1127.0) - 1.0); };
  const double lo = mel(o.low_hz), hi = mel(o.high_hz);
  std::vector<double> out(static_cast<std::size_t>(o.num_bins));
  for (int b = 0; b < o.num_bins; ++b) {
    const double left = hz(lo + (hi - lo) * b / (o.num_bins + 1));
    const double centre = hz(lo + (hi - lo) * (b + 1) / (o.num_bins + 1));
    const double right = hz(lo + (hi - lo) * (b + 2) / (o.num_bins + 1));
    double energy = 0;
    for (std::size_t k = 0; k < power.size(); ++k) {
      const double f = static_cast<double>(k) * o.sample_rate / static_cast<double>(nfft);
      double w = 0;
      if (f > left && f <= centre) w = (f - left) / (centre - left);
      if (f > centre && f < right) w = (right - f) / (right - centre);
      energy += w * power[k];
    }
    out[static_cast<std::size_t>(b)] = std::log(std::max(energy, static_cast<double>(o.energy_floor)));
  }
  return out;
}

}  // namespace

TEST_CASE("FFT matches a direct DFT on random data") {
  marvin::perception::Fft fft(64);
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> dist(-1, 1);
  std::vector<std::complex<float>> data(64);
  for (auto& v : data) v = {dist(rng), dist(rng)};
  const auto input = data;
  fft.forward(data);
  for (std::size_t k = 0; k < 64; ++k) {
    std::complex<double> sum = 0;
    for (std::size_t n = 0; n < 64; ++n) {
      sum += std::complex<double>(input[n]) *
             std::polar(1.0, -2 * std::numbers::pi * static_cast<double>(k * n) / 64.0);
    }
    CHECK(std::abs(std::complex<double>(data[k]) - sum) < 1e-4);
  }
  CHECK_THROWS_AS(marvin::perception::Fft(48), std::invalid_argument);
}

TEST_CASE("log-mel of a 1 kHz tone matches the direct-DFT reference") {
  LogMelOptions options;  // 16 kHz, 25 ms / 10 ms, 40 bins
  LogMelExtractor extractor(options);
  REQUIRE(extractor.frame_length() == 400);
  REQUIRE(extractor.hop_length() == 160);
  REQUIRE(extractor.num_bins() == 40);

  const std::vector<float> frame = tone(1000.0, 0.5, 400);
  std::vector<float> got(40);
  extractor.compute(frame, got);
  const std::vector<double> want = reference_log_mel(frame, options);

  double max_want = -1e30;
  std::size_t peak_want = 0, peak_got = 0;
  for (std::size_t b = 0; b < 40; ++b) {
    if (want[b] > max_want) {
      max_want = want[b];
      peak_want = b;
    }
    if (got[b] > got[peak_got]) peak_got = b;
  }
  // Bins within 60 dB of the peak agree closely; far below it float rounding dominates.
  for (std::size_t b = 0; b < 40; ++b) {
    CAPTURE(b);
    if (want[b] > max_want - std::log(1e6)) CHECK(got[b] == doctest::Approx(want[b]).epsilon(1e-3));
  }
  CHECK(peak_got == peak_want);
  // The peak bin is the one whose triangle covers 1 kHz best.
  const float centre_hz = marvin::perception::mel_to_hz(
      marvin::perception::hz_to_mel(options.low_hz) +
      (marvin::perception::hz_to_mel(options.high_hz) - marvin::perception::hz_to_mel(options.low_hz)) *
          static_cast<float>(peak_got + 1) / 41.0f);
  CHECK(std::abs(centre_hz - 1000.0f) < 80.0f);
}

TEST_CASE("streaming frames equal framewise computation and allocate nothing") {
  LogMelExtractor extractor;
  const std::vector<float> signal = tone(440.0, 0.3, 16000);
  std::vector<std::int16_t> pcm(signal.size());
  for (std::size_t i = 0; i < signal.size(); ++i) {
    pcm[i] = static_cast<std::int16_t>(std::lrint(signal[i] * 32768.0f));
  }
  std::vector<float> frames;
  frames.reserve(200 * 40);
  std::size_t count = 0;
  const std::size_t allocations_before = g_allocations;
  // Odd chunk sizes, as a sound card or aggregator would deliver.
  for (std::size_t pos = 0, step = 1; pos < pcm.size(); pos += step, step = step * 7 % 331 + 1) {
    const std::size_t n = std::min(step, pcm.size() - pos);
    count += extractor.push(std::span<const std::int16_t>(pcm).subspan(pos, n),
                            [&](std::span<const float> bins) {
                              frames.insert(frames.end(), bins.begin(), bins.end());
                            });
  }
  CHECK(g_allocations == allocations_before);
  CHECK(count == 1 + (16000 - 400) / 160);
  REQUIRE(frames.size() == count * 40);

  std::vector<float> window(400), expected(40);
  for (std::size_t f : {std::size_t{0}, std::size_t{1}, std::size_t{57}, count - 1}) {
    for (std::size_t i = 0; i < 400; ++i) window[i] = static_cast<float>(pcm[f * 160 + i]) / 32768.0f;
    extractor.compute(window, expected);
    for (std::size_t b = 0; b < 40; ++b) CHECK(frames[f * 40 + b] == doctest::Approx(expected[b]));
  }
}

TEST_CASE("silence sits at the energy floor and bad options are refused") {
  LogMelExtractor extractor;
  std::vector<float> frame(400, 0.0f), out(40);
  extractor.compute(frame, out);
  for (float v : out) CHECK(v == doctest::Approx(std::log(1e-10f)));

  LogMelOptions bad;
  bad.fft_size = 256;  // shorter than the 400-sample window
  CHECK_THROWS_WITH_AS(LogMelExtractor{bad}, doctest::Contains("fft_size 256"), std::invalid_argument);
  bad = {};
  bad.high_hz = 9000;
  CHECK_THROWS_WITH_AS(LogMelExtractor{bad}, doctest::Contains("high_hz"), std::invalid_argument);
}
