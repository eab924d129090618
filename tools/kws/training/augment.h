// Audio augmentations and generated noises for training the keyword spotter (16 kHz mono
// float in [-1, 1]). All randomness comes from the caller's generator.
#pragma once

#include <cstdint>
#include <random>
#include <span>
#include <vector>

namespace marvin::perception::kws {

enum class NoiseColour { white, pink, brown };

// `count` samples of coloured noise with RMS 1 before clipping-free scaling to `rms`.
std::vector<float> make_noise(NoiseColour colour, std::size_t count, float rms,
                              std::mt19937_64& rng);

float rms(std::span<const float> x);

// Time-stretch by `rate` (> 1 is faster/shorter) keeping the pitch: WSOLA with 32 ms Hann
// frames, half overlap and a ±8 ms similarity search.
std::vector<float> time_stretch(std::span<const float> x, double rate);

// Speed and pitch together by `factor` (> 1 faster and higher): resampling.
std::vector<float> change_speed_and_pitch(std::span<const float> x, double factor);

// Pitch by `semitones` keeping the duration: resample, then time-stretch back.
std::vector<float> shift_pitch(std::span<const float> x, double semitones);

// Harmonic-percussive separation (Fitzgerald 2010): STFT (512, hop 128), median filters of
// 17 along time (harmonic) and frequency (percussive), soft masks. Returns the harmonic part
// scaled by `harmonic_gain` plus the percussive part scaled by `percussive_gain`.
std::vector<float> hpss_remix(std::span<const float> x, float harmonic_gain, float percussive_gain);

// Adds `noise` (cycled / cropped from a random offset) to `x` at signal-to-noise ratio
// `snr_db` relative to x's RMS over its active part.
void add_noise_at_snr(std::vector<float>& x, std::span<const float> noise, float snr_db,
                      std::mt19937_64& rng);

// Room reverberation: `x` convolved with a synthetic impulse response, a direct path followed,
// after 2..8 ms, by sparse random-sign taps ("velvet noise", about 2000 a second) whose level
// decays by 60 dB over `rt60_s`; the tail's energy is `reverb_db` relative to the direct path's.
// The result keeps x's length (the tail past the end is dropped) and its peak level.
std::vector<float> add_reverb(std::span<const float> x, float rt60_s, float reverb_db,
                              std::mt19937_64& rng);

// A small or cheap microphone: second-order Butterworth high-pass at `low_hz` and low-pass at
// `high_hz` (16 kHz), in place.
void band_limit(std::vector<float>& x, float low_hz, float high_hz);

// Dropped audio: `spans` stretches of 50..300 ms, each starting at a random sample in
// [from, x.size()), set to digital silence, as when a microphone or a link loses frames (real
// recordings have them). In place; returns how many samples it changed.
std::size_t drop_out(std::vector<float>& x, std::size_t from, int spans, std::mt19937_64& rng);

// Strips leading and trailing parts quieter than `threshold_db` below the peak (20 ms frames).
std::vector<float> trim_silence(std::span<const float> x, float threshold_db = 40.0f);

}  // namespace marvin::perception::kws
