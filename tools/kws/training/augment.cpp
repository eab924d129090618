#include "kws/training/augment.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>

#include "devices/audio/resampler.h"
#include "perception/fft.h"

namespace marvin::perception::kws {

float rms(std::span<const float> x) {
  if (x.empty()) return 0.0f;
  double s = 0.0;
  for (float v : x) s += static_cast<double>(v) * v;
  return static_cast<float>(std::sqrt(s / static_cast<double>(x.size())));
}

std::vector<float> make_noise(NoiseColour colour, std::size_t count, float level,
                              std::mt19937_64& rng) {
  std::normal_distribution<float> gauss(0.0f, 1.0f);
  std::vector<float> out(count);
  // Pink: Paul Kellet's economy filter; brown: leaky integrator.
  float b0 = 0, b1 = 0, b2 = 0, brown = 0;
  for (float& v : out) {
    const float w = gauss(rng);
    switch (colour) {
      case NoiseColour::white:
        v = w;
        break;
      case NoiseColour::pink:
        b0 = 0.99765f * b0 + w * 0.0990460f;
        b1 = 0.96300f * b1 + w * 0.2965164f;
        b2 = 0.57000f * b2 + w * 1.0526913f;
        v = b0 + b1 + b2 + w * 0.1848f;
        break;
      case NoiseColour::brown:
        brown = 0.995f * brown + 0.1f * w;
        v = brown;
        break;
    }
  }
  const float r = rms(out);
  if (r > 0.0f) {
    for (float& v : out) v *= level / r;
  }
  return out;
}

std::vector<float> time_stretch(std::span<const float> x, double rate) {
  constexpr int n = 512, hop = 256, tolerance = 128;
  if (x.size() < static_cast<std::size_t>(n) || std::fabs(rate - 1.0) < 1e-3) {
    return std::vector<float>(x.begin(), x.end());
  }
  std::vector<float> window(n);
  for (int i = 0; i < n; ++i) {
    window[static_cast<std::size_t>(i)] =
        0.5f - 0.5f * std::cos(2.0f * std::numbers::pi_v<float> * static_cast<float>(i) / n);
  }
  const std::size_t out_len = static_cast<std::size_t>(static_cast<double>(x.size()) / rate);
  std::vector<float> out(out_len + n, 0.0f), norm(out_len + n, 0.0f);
  const std::ptrdiff_t len = static_cast<std::ptrdiff_t>(x.size());
  auto at = [&](std::ptrdiff_t i) {
    return i >= 0 && i < len ? x[static_cast<std::size_t>(i)] : 0.0f;
  };
  std::ptrdiff_t prev = 0;  // where the previous frame was taken from
  for (std::size_t k = 0; k * hop < out_len; ++k) {
    const std::ptrdiff_t nominal = static_cast<std::ptrdiff_t>(static_cast<double>(k * hop) * rate);
    std::ptrdiff_t best = nominal;
    if (k > 0) {
      // The natural continuation of the previous frame is prev + hop; pick the offset around
      // `nominal` that looks most like it.
      double best_score = -1e30;
      for (std::ptrdiff_t d = -tolerance; d <= tolerance; d += 4) {
        const std::ptrdiff_t cand = nominal + d;
        double score = 0.0;
        for (int i = 0; i < hop; i += 2)
          score += static_cast<double>(at(cand + i)) * at(prev + hop + i);
        if (score > best_score) {
          best_score = score;
          best = cand;
        }
      }
    }
    for (int i = 0; i < n; ++i) {
      const std::size_t o = k * hop + static_cast<std::size_t>(i);
      out[o] += at(best + i) * window[static_cast<std::size_t>(i)];
      norm[o] += window[static_cast<std::size_t>(i)];
    }
    prev = best;
  }
  out.resize(out_len);
  for (std::size_t i = 0; i < out_len; ++i) {
    if (norm[i] > 1e-3f) out[i] /= norm[i];
  }
  return out;
}

std::vector<float> change_speed_and_pitch(std::span<const float> x, double factor) {
  // Playing 16 kHz audio as if it were at 16 kHz * factor: resample from rate*factor to rate.
  const int from = static_cast<int>(std::lround(16000.0 * factor));
  return audio::resample(x, from, 16000);
}

std::vector<float> shift_pitch(std::span<const float> x, double semitones) {
  const double factor = std::pow(2.0, semitones / 12.0);
  std::vector<float> y = change_speed_and_pitch(x, factor);  // shorter and higher
  return time_stretch(y, 1.0 / factor);                      // back to the length
}

namespace {

float median(std::vector<float>& v) {
  auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

}  // namespace

std::vector<float> hpss_remix(std::span<const float> x, float harmonic_gain,
                              float percussive_gain) {
  constexpr int n = 512, hop = 128, bins = n / 2 + 1, kernel = 17;
  if (x.size() < static_cast<std::size_t>(n)) return std::vector<float>(x.begin(), x.end());
  const Fft fft(n);
  std::vector<float> window(n);
  for (int i = 0; i < n; ++i) {
    window[static_cast<std::size_t>(i)] =
        0.5f - 0.5f * std::cos(2.0f * std::numbers::pi_v<float> * static_cast<float>(i) / n);
  }
  const std::size_t frames = (x.size() - n) / hop + 1;
  std::vector<std::vector<std::complex<float>>> spec(frames, std::vector<std::complex<float>>(n));
  std::vector<float> mag(frames * bins);
  for (std::size_t f = 0; f < frames; ++f) {
    for (int i = 0; i < n; ++i)
      spec[f][static_cast<std::size_t>(i)] =
          x[f * hop + static_cast<std::size_t>(i)] * window[static_cast<std::size_t>(i)];
    fft.forward(spec[f]);
    for (int b = 0; b < bins; ++b)
      mag[f * bins + static_cast<std::size_t>(b)] = std::abs(spec[f][static_cast<std::size_t>(b)]);
  }
  std::vector<float> harm(frames * bins), perc(frames * bins), buf;
  for (std::size_t f = 0; f < frames; ++f) {
    for (int b = 0; b < bins; ++b) {
      buf.clear();
      for (int d = -kernel / 2; d <= kernel / 2; ++d) {
        const std::ptrdiff_t ff = static_cast<std::ptrdiff_t>(f) + d;
        if (ff >= 0 && ff < static_cast<std::ptrdiff_t>(frames))
          buf.push_back(mag[static_cast<std::size_t>(ff) * bins + static_cast<std::size_t>(b)]);
      }
      harm[f * bins + static_cast<std::size_t>(b)] = median(buf);
      buf.clear();
      for (int d = -kernel / 2; d <= kernel / 2; ++d) {
        const int bb = b + d;
        if (bb >= 0 && bb < bins) buf.push_back(mag[f * bins + static_cast<std::size_t>(bb)]);
      }
      perc[f * bins + static_cast<std::size_t>(b)] = median(buf);
    }
  }
  std::vector<float> out(x.size(), 0.0f), norm(x.size(), 0.0f);
  for (std::size_t f = 0; f < frames; ++f) {
    auto& s = spec[f];
    for (int b = 0; b < bins; ++b) {
      const std::size_t k = f * bins + static_cast<std::size_t>(b);
      const float h2 = harm[k] * harm[k], p2 = perc[k] * perc[k];
      const float mh = h2 + p2 > 0.0f ? h2 / (h2 + p2) : 0.5f;
      const float gain = harmonic_gain * mh + percussive_gain * (1.0f - mh);
      s[static_cast<std::size_t>(b)] *= gain;
      if (b > 0 && b < n / 2)
        s[static_cast<std::size_t>(n - b)] = std::conj(s[static_cast<std::size_t>(b)]);
    }
    // Inverse through the forward transform: ifft(X) = conj(fft(conj(X))) / n.
    for (auto& v : s) v = std::conj(v);
    fft.forward(s);
    for (int i = 0; i < n; ++i) {
      const std::size_t o = f * hop + static_cast<std::size_t>(i);
      out[o] += s[static_cast<std::size_t>(i)].real() / n * window[static_cast<std::size_t>(i)];
      norm[o] += window[static_cast<std::size_t>(i)] * window[static_cast<std::size_t>(i)];
    }
  }
  for (std::size_t i = 0; i < out.size(); ++i) {
    out[i] = norm[i] > 1e-3f ? out[i] / norm[i] : x[i];
  }
  return out;
}

void add_noise_at_snr(std::vector<float>& x, std::span<const float> noise, float snr_db,
                      std::mt19937_64& rng) {
  if (noise.empty() || x.empty()) return;
  // Signal level over the active part: the RMS of the loudest half of 20 ms frames.
  std::vector<float> frame_rms;
  for (std::size_t i = 0; i + 320 <= x.size(); i += 320) {
    frame_rms.push_back(rms(std::span<const float>(x).subspan(i, 320)));
  }
  std::sort(frame_rms.begin(), frame_rms.end(), std::greater<>());
  double sig = 0.0;
  const std::size_t half = std::max<std::size_t>(1, frame_rms.size() / 2);
  for (std::size_t i = 0; i < half && i < frame_rms.size(); ++i)
    sig += static_cast<double>(frame_rms[i]) * frame_rms[i];
  sig = std::sqrt(sig / static_cast<double>(half));
  std::uniform_int_distribution<std::size_t> start(0, noise.size() - 1);
  std::size_t pos = start(rng);
  std::vector<float> seg(x.size());
  for (float& v : seg) {
    v = noise[pos];
    pos = (pos + 1) % noise.size();
  }
  const float nr = rms(seg);
  if (nr <= 0.0f || sig <= 0.0) return;
  const float gain = static_cast<float>(sig / std::pow(10.0, snr_db / 20.0)) / nr;
  for (std::size_t i = 0; i < x.size(); ++i) x[i] += gain * seg[i];
}

std::size_t drop_out(std::vector<float>& x, std::size_t from, int spans, std::mt19937_64& rng) {
  std::size_t silenced = 0;
  if (from >= x.size()) return 0;
  std::uniform_int_distribution<std::size_t> where(from, x.size() - 1), length(800, 4800);
  for (int s = 0; s < spans; ++s) {
    const std::size_t begin = where(rng);
    const std::size_t end = std::min(x.size(), begin + length(rng));
    for (std::size_t i = begin; i < end; ++i) {
      silenced += x[i] != 0.0f ? 1 : 0;
      x[i] = 0.0f;
    }
  }
  return silenced;
}

std::vector<float> trim_silence(std::span<const float> x, float threshold_db) {
  constexpr std::size_t frame = 320;
  float peak = 0.0f;
  std::vector<float> levels;
  for (std::size_t i = 0; i < x.size(); i += frame) {
    const float r = rms(x.subspan(i, std::min(frame, x.size() - i)));
    levels.push_back(r);
    peak = std::max(peak, r);
  }
  if (peak <= 0.0f) return {};
  const float floor = peak * std::pow(10.0f, -threshold_db / 20.0f);
  std::size_t first = 0, last = levels.size();
  while (first < levels.size() && levels[first] < floor) ++first;
  while (last > first && levels[last - 1] < floor) --last;
  const std::size_t b = first * frame, e = std::min(x.size(), last * frame);
  return std::vector<float>(x.begin() + static_cast<std::ptrdiff_t>(b),
                            x.begin() + static_cast<std::ptrdiff_t>(e));
}

std::vector<float> add_reverb(std::span<const float> x, float rt60_s, float reverb_db,
                              std::mt19937_64& rng) {
  constexpr float kRate = 16000.0f;
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  // The tail: one tap in each 8-sample cell (2000 a second), random sign, decaying to -60 dB
  // at rt60 (amplitude exp(-6.9 t / rt60)).
  struct Tap {
    std::size_t delay;
    float gain;
  };
  std::vector<Tap> taps;
  const auto first = static_cast<std::size_t>((0.002f + 0.006f * u(rng)) * kRate);
  const auto length = static_cast<std::size_t>(rt60_s * kRate);
  double energy = 0.0;
  for (std::size_t cell = first; cell < length; cell += 8) {
    const std::size_t d = cell + static_cast<std::size_t>(u(rng) * 8.0f);
    const float a =
        std::exp(-6.9f * static_cast<float>(d) / (rt60_s * kRate)) * (u(rng) < 0.5f ? -1.0f : 1.0f);
    taps.push_back({d, a});
    energy += static_cast<double>(a) * a;
  }
  const float scale = energy > 0.0
                          ? static_cast<float>(std::pow(10.0, reverb_db / 20.0) / std::sqrt(energy))
                          : 0.0f;
  std::vector<float> y(x.begin(), x.end());
  for (const Tap& t : taps) {
    const float g = t.gain * scale;
    for (std::size_t i = t.delay; i < y.size(); ++i) y[i] += g * x[i - t.delay];
  }
  float peak_in = 0.0f, peak_out = 0.0f;
  for (float v : x) peak_in = std::max(peak_in, std::fabs(v));
  for (float v : y) peak_out = std::max(peak_out, std::fabs(v));
  if (peak_out > 0.0f) {
    for (float& v : y) v *= peak_in / peak_out;
  }
  return y;
}

namespace {

// One second-order Butterworth section (RBJ cookbook, Q = 1/sqrt 2), direct form I.
void biquad(std::vector<float>& x, float hz, bool high_pass) {
  const double w = 2.0 * std::numbers::pi * hz / 16000.0;
  const double alpha = std::sin(w) / std::sqrt(2.0);
  const double c = std::cos(w);
  const double b0 = high_pass ? (1.0 + c) / 2.0 : (1.0 - c) / 2.0;
  const double b1 = high_pass ? -(1.0 + c) : 1.0 - c;
  const double a0 = 1.0 + alpha, a1 = -2.0 * c, a2 = 1.0 - alpha;
  double x1 = 0.0, x2 = 0.0, y1 = 0.0, y2 = 0.0;
  for (float& v : x) {
    const double in = v;
    const double out = (b0 * in + b1 * x1 + b0 * x2 - a1 * y1 - a2 * y2) / a0;
    x2 = x1;
    x1 = in;
    y2 = y1;
    y1 = out;
    v = static_cast<float>(out);
  }
}

}  // namespace

void band_limit(std::vector<float>& x, float low_hz, float high_hz) {
  biquad(x, low_hz, true);
  biquad(x, high_hz, false);
}

}  // namespace marvin::perception::kws
