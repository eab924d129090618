// Log-mel filter bank energies: the acoustic features of the voice path.
//
// Each frame is `window_ms` of audio taken every `hop_ms` (25 ms / 10 ms at 16 kHz:
// 400 samples every 160). A frame has its mean removed, is multiplied by a Hamming window,
// zero-padded to `fft_size`, transformed; the power spectrum |X[k]|^2 is weighted by
// `num_bins` triangular filters evenly spaced on the mel scale (HTK: 2595 log10(1 + f/700))
// between `low_hz` and `high_hz`, each filter peaking at 1; the result is ln(max(energy,
// `energy_floor`)). Samples are floats in [-1, 1] (PCM16 / 32768).
//
// The neural keyword spotter (issue 9) trains and runs on exactly these frames, so changing
// a default changes its model's input: bump the model format's feature settings with it.
#pragma once

#include <complex>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "perception/fft.h"

namespace marvin::perception {

struct LogMelOptions {
  int sample_rate = 16000;
  int window_ms = 25;
  int hop_ms = 10;
  int num_bins = 40;
  int fft_size = 512;       // power of two >= window length
  float low_hz = 20.0f;
  float high_hz = 8000.0f;  // <= sample_rate / 2
  float energy_floor = 1e-10f;
};

// Frequency in Hz <-> mel (HTK formula).
float hz_to_mel(float hz);
float mel_to_hz(float mel);

class LogMelExtractor {
 public:
  // Validates the options (throws std::invalid_argument naming the bad field) and sizes
  // every buffer; nothing is allocated after construction.
  explicit LogMelExtractor(const LogMelOptions& options = {});

  const LogMelOptions& options() const { return options_; }
  std::size_t frame_length() const { return frame_length_; }  // samples per window (400)
  std::size_t hop_length() const { return hop_length_; }      // samples per hop (160)
  std::size_t num_bins() const { return static_cast<std::size_t>(options_.num_bins); }

  // One frame: `window` holds exactly frame_length() samples, `out` num_bins() values.
  void compute(std::span<const float> window, std::span<float> out);

  // Streaming: appends samples; for each complete frame calls on_frame(std::span<const
  // float> bins) in order. The first frame covers samples [0, frame_length), the next
  // starts hop_length later. Returns the number of frames produced. Allocation-free.
  template <typename OnFrame>
  std::size_t push(std::span<const std::int16_t> samples, OnFrame&& on_frame) {
    std::size_t produced = 0;
    for (std::int16_t s : samples) {
      pending_[filled_++] = static_cast<float>(s) / 32768.0f;
      if (filled_ == frame_length_) {
        compute(pending_, frame_);
        on_frame(std::span<const float>(frame_));
        ++produced;
        shift_by_hop();
      }
    }
    return produced;
  }

  // Forgets buffered samples (next push starts a new stream).
  void reset() { filled_ = 0; }

  // The filter weights (num_bins() rows of fft_size/2+1), for inspection and tests.
  std::span<const float> filter(std::size_t bin) const;

 private:
  void shift_by_hop();

  LogMelOptions options_;
  std::size_t frame_length_;
  std::size_t hop_length_;
  std::size_t spectrum_size_;
  Fft fft_;
  std::vector<float> window_function_;
  std::vector<float> filters_;  // num_bins * spectrum_size_
  std::vector<std::size_t> filter_begin_;
  std::vector<std::size_t> filter_end_;
  std::vector<std::complex<float>> fft_buffer_;
  std::vector<float> power_;
  std::vector<float> pending_;
  std::size_t filled_ = 0;
  std::vector<float> frame_;
};

}  // namespace marvin::perception
