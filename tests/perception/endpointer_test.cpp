#include <doctest/doctest.h>

#include <cmath>
#include <cstdint>
#include <numbers>
#include <random>
#include <vector>

#include "perception/endpointer.h"

namespace {

using marvin::perception::Endpointer;
using marvin::perception::EndpointState;

void append_silence(std::vector<std::int16_t>& out, int ms, double noise_amplitude = 0.0) {
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, noise_amplitude * 32767.0);
  for (int i = 0; i < ms * 16; ++i) {
    out.push_back(static_cast<std::int16_t>(noise_amplitude > 0 ? std::lrint(noise(rng)) : 0));
  }
}

void append_tone(std::vector<std::int16_t>& out, int ms, double amplitude = 0.3) {
  for (int i = 0; i < ms * 16; ++i) {
    out.push_back(static_cast<std::int16_t>(
        std::lrint(amplitude * 32767.0 * std::sin(2 * std::numbers::pi * 300.0 * i / 16000.0))));
  }
}

}  // namespace

TEST_CASE("end of speech after the trailing silence") {
  std::vector<std::int16_t> audio;
  append_silence(audio, 300);
  append_tone(audio, 700);
  append_silence(audio, 150);  // a pause inside the utterance
  append_tone(audio, 300);
  append_silence(audio, 1000);

  Endpointer endpointer;  // the default trailing silence (250 ms)
  const int trailing_ms = marvin::perception::EndpointerOptions{}.trailing_silence_ms;
  EndpointState state = EndpointState::kWaitingForSpeech;
  std::vector<EndpointState> seen;
  for (std::size_t pos = 0; pos < audio.size(); pos += 333) {
    const std::size_t n = std::min<std::size_t>(333, audio.size() - pos);
    state = endpointer.push(std::span<const std::int16_t>(audio).subspan(pos, n));
    if (seen.empty() || seen.back() != state) seen.push_back(state);
  }
  CHECK(seen == std::vector<EndpointState>{EndpointState::kWaitingForSpeech,
                                           EndpointState::kInSpeech, EndpointState::kEnded});
  CHECK(endpointer.speech_begin() == 300 * 16);
  CHECK(endpointer.speech_end() == (300 + 700 + 150 + 300) * 16);
  // Decided exactly that long after the last speech frame, and consumed nothing after that.
  CHECK(endpointer.samples_seen() == endpointer.speech_end() + trailing_ms * 16);
  const std::int64_t decided = endpointer.samples_seen();
  endpointer.push(audio);
  CHECK(endpointer.samples_seen() == decided);
}

TEST_CASE("no speech times out; speech over background noise is still found") {
  marvin::perception::EndpointerOptions options;
  options.no_speech_timeout_ms = 2000;
  Endpointer endpointer(options);
  std::vector<std::int16_t> quiet;
  append_silence(quiet, 3000, 0.003);  // about -50 dBFS hiss
  CHECK(endpointer.push(quiet) == EndpointState::kTimedOut);
  CHECK(endpointer.samples_seen() == 2000 * 16);

  endpointer.reset();
  std::vector<std::int16_t> audio;
  append_silence(audio, 500, 0.003);
  append_tone(audio, 500);
  append_silence(audio, 800, 0.003);
  CHECK(endpointer.push(audio) == EndpointState::kEnded);
  CHECK(endpointer.speech_begin() == doctest::Approx(500 * 16).epsilon(0.05));
  CHECK(endpointer.speech_end() == doctest::Approx(1000 * 16).epsilon(0.05));
}

TEST_CASE("speech that never stops is cut at max_speech_ms") {
  marvin::perception::EndpointerOptions options;
  options.max_speech_ms = 1000;
  Endpointer endpointer(options);
  std::vector<std::int16_t> audio;
  append_tone(audio, 3000);
  CHECK(endpointer.push(audio) == EndpointState::kEnded);
  CHECK(endpointer.samples_seen() <= 1100 * 16);
}
