#include "perception/log_mel.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace marvin::perception {
namespace {

void require(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument("LogMelOptions: " + what);
}

}  // namespace

float hz_to_mel(float hz) { return 2595.0f * std::log10(1.0f + hz / 700.0f); }
float mel_to_hz(float mel) { return 700.0f * (std::pow(10.0f, mel / 2595.0f) - 1.0f); }

LogMelExtractor::LogMelExtractor(const LogMelOptions& options)
    : options_(options),
      frame_length_(static_cast<std::size_t>(options.sample_rate) * options.window_ms / 1000),
      hop_length_(static_cast<std::size_t>(options.sample_rate) * options.hop_ms / 1000),
      spectrum_size_(static_cast<std::size_t>(options.fft_size) / 2 + 1),
      fft_(static_cast<std::size_t>(options.fft_size > 0 ? options.fft_size : 0)) {
  require(options.sample_rate > 0, "sample_rate must be positive");
  require(options.window_ms > 0 && options.hop_ms > 0, "window_ms and hop_ms must be positive");
  require(frame_length_ <= static_cast<std::size_t>(options.fft_size),
          "fft_size " + std::to_string(options.fft_size) + " is shorter than the window (" +
              std::to_string(frame_length_) + " samples)");
  require(hop_length_ <= frame_length_, "hop_ms must not exceed window_ms");
  require(options.num_bins > 0, "num_bins must be positive");
  require(options.low_hz >= 0 && options.low_hz < options.high_hz &&
              options.high_hz <= static_cast<float>(options.sample_rate) / 2,
          "need 0 <= low_hz < high_hz <= sample_rate / 2");

  window_function_.resize(frame_length_);
  for (std::size_t n = 0; n < frame_length_; ++n) {
    window_function_[n] = static_cast<float>(
        0.54 - 0.46 * std::cos(2.0 * std::numbers::pi * static_cast<double>(n) /
                               static_cast<double>(frame_length_ - 1)));
  }

  // Triangles between consecutive mel-spaced centre frequencies.
  const std::size_t bins = num_bins();
  const float mel_low = hz_to_mel(options.low_hz);
  const float mel_high = hz_to_mel(options.high_hz);
  std::vector<float> edges_hz(bins + 2);
  for (std::size_t i = 0; i < bins + 2; ++i) {
    edges_hz[i] = mel_to_hz(mel_low + (mel_high - mel_low) * static_cast<float>(i) /
                                          static_cast<float>(bins + 1));
  }
  const float hz_per_bin = static_cast<float>(options.sample_rate) / static_cast<float>(options.fft_size);
  filters_.assign(bins * spectrum_size_, 0.0f);
  filter_begin_.assign(bins, spectrum_size_);
  filter_end_.assign(bins, 0);
  for (std::size_t b = 0; b < bins; ++b) {
    const float left = edges_hz[b], centre = edges_hz[b + 1], right = edges_hz[b + 2];
    for (std::size_t k = 0; k < spectrum_size_; ++k) {
      const float f = static_cast<float>(k) * hz_per_bin;
      float w = 0.0f;
      if (f > left && f <= centre) w = (f - left) / (centre - left);
      else if (f > centre && f < right) w = (right - f) / (right - centre);
      if (w > 0.0f) {
        filters_[b * spectrum_size_ + k] = w;
        filter_begin_[b] = std::min(filter_begin_[b], k);
        filter_end_[b] = k + 1;
      }
    }
    if (filter_end_[b] == 0) filter_begin_[b] = 0;  // narrower than one FFT bin: empty
  }

  fft_buffer_.resize(static_cast<std::size_t>(options.fft_size));
  power_.resize(spectrum_size_);
  pending_.resize(frame_length_);
  frame_.resize(bins);
}

void LogMelExtractor::compute(std::span<const float> window, std::span<float> out) {
  if (window.size() != frame_length_ || out.size() != num_bins()) {
    throw std::invalid_argument("LogMelExtractor::compute: expected " +
                                std::to_string(frame_length_) + " samples and " +
                                std::to_string(num_bins()) + " outputs");
  }
  float mean = 0.0f;
  for (float s : window) mean += s;
  mean /= static_cast<float>(frame_length_);
  for (std::size_t n = 0; n < frame_length_; ++n) {
    fft_buffer_[n] = {(window[n] - mean) * window_function_[n], 0.0f};
  }
  std::fill(fft_buffer_.begin() + static_cast<std::ptrdiff_t>(frame_length_), fft_buffer_.end(),
            std::complex<float>{});
  fft_.forward(fft_buffer_);
  for (std::size_t k = 0; k < spectrum_size_; ++k) power_[k] = std::norm(fft_buffer_[k]);
  for (std::size_t b = 0; b < num_bins(); ++b) {
    const float* weights = &filters_[b * spectrum_size_];
    float energy = 0.0f;
    for (std::size_t k = filter_begin_[b]; k < filter_end_[b]; ++k) energy += weights[k] * power_[k];
    out[b] = std::log(std::max(energy, options_.energy_floor));
  }
}

std::span<const float> LogMelExtractor::filter(std::size_t bin) const {
  return std::span<const float>(filters_).subspan(bin * spectrum_size_, spectrum_size_);
}

void LogMelExtractor::shift_by_hop() {
  std::copy(pending_.begin() + static_cast<std::ptrdiff_t>(hop_length_), pending_.end(),
            pending_.begin());
  filled_ = frame_length_ - hop_length_;
}

}  // namespace marvin::perception
