#include "devices/audio/resampler.h"

#include <soxr.h>

#include <cmath>
#include <stdexcept>
#include <string>

namespace marvin::audio {

std::vector<float> mix_to_mono(std::span<const float> interleaved, int channels) {
  if (channels <= 0) throw std::runtime_error("mix_to_mono: channel count must be positive");
  if (channels == 1) return {interleaved.begin(), interleaved.end()};
  const std::size_t frames = interleaved.size() / channels;
  std::vector<float> mono(frames);
  for (std::size_t f = 0; f < frames; ++f) {
    float sum = 0.0f;
    for (int c = 0; c < channels; ++c) sum += interleaved[f * channels + c];
    mono[f] = sum / static_cast<float>(channels);
  }
  return mono;
}

std::vector<float> resample(std::span<const float> mono, int from_rate, int to_rate) {
  if (from_rate <= 0 || to_rate <= 0) {
    throw std::runtime_error("resample: rates must be positive (got " +
                             std::to_string(from_rate) + " -> " + std::to_string(to_rate) +
                             ")");
  }
  if (from_rate == to_rate) return {mono.begin(), mono.end()};
  const double ratio = static_cast<double>(to_rate) / from_rate;
  std::vector<float> out(static_cast<std::size_t>(std::ceil(static_cast<double>(mono.size()) * ratio)) + 16);
  std::size_t done = 0;
  const soxr_io_spec_t io = soxr_io_spec(SOXR_FLOAT32_I, SOXR_FLOAT32_I);
  const soxr_quality_spec_t quality = soxr_quality_spec(SOXR_HQ, 0);
  soxr_error_t error = soxr_oneshot(from_rate, to_rate, 1, mono.data(), mono.size(), nullptr,
                                    out.data(), out.size(), &done, &io, &quality, nullptr);
  if (error) throw std::runtime_error(std::string("resample: libsoxr: ") + error);
  out.resize(done);
  return out;
}

std::vector<float> to_speech_format(const SoundBuffer& sound) {
  return resample(mix_to_mono(sound.samples, sound.channels), sound.sample_rate,
                  kSpeechSampleRate);
}

struct StreamResampler::Impl {
  soxr_t soxr = nullptr;
  double ratio = 1.0;
};

StreamResampler::StreamResampler(int from_rate, int to_rate) : impl_(std::make_unique<Impl>()) {
  if (from_rate <= 0 || to_rate <= 0) {
    throw std::runtime_error("StreamResampler: rates must be positive");
  }
  impl_->ratio = static_cast<double>(to_rate) / from_rate;
  soxr_error_t error = nullptr;
  const soxr_io_spec_t io = soxr_io_spec(SOXR_FLOAT32_I, SOXR_FLOAT32_I);
  const soxr_quality_spec_t quality = soxr_quality_spec(SOXR_HQ, 0);
  impl_->soxr = soxr_create(from_rate, to_rate, 1, &error, &io, &quality, nullptr);
  if (error) throw std::runtime_error(std::string("StreamResampler: libsoxr: ") + error);
}

StreamResampler::~StreamResampler() { soxr_delete(impl_->soxr); }

void StreamResampler::process(std::span<const float> in, std::vector<float>& out) {
  const std::size_t start = out.size();
  out.resize(start + static_cast<std::size_t>(std::ceil(static_cast<double>(in.size()) * impl_->ratio)) + 64);
  std::size_t used = 0;
  std::size_t done = 0;
  soxr_error_t error = soxr_process(impl_->soxr, in.data(), in.size(), &used, out.data() + start,
                                    out.size() - start, &done);
  if (error) throw std::runtime_error(std::string("StreamResampler: libsoxr: ") + error);
  out.resize(start + done);
}

void StreamResampler::flush(std::vector<float>& out) {
  std::vector<float> tail(4096);
  for (;;) {
    std::size_t done = 0;
    soxr_error_t error =
        soxr_process(impl_->soxr, nullptr, 0, nullptr, tail.data(), tail.size(), &done);
    if (error) throw std::runtime_error(std::string("StreamResampler: libsoxr: ") + error);
    if (done == 0) break;
    out.insert(out.end(), tail.begin(), tail.begin() + static_cast<std::ptrdiff_t>(done));
  }
}

}  // namespace marvin::audio
