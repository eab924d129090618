#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>
#include <numbers>
#include <string>
#include <unistd.h>

#include "devices/audio/alsa_device.h"
#include "devices/audio/resampler.h"
#include "devices/audio/sound_file.h"

namespace fs = std::filesystem;
using namespace marvin::audio;

namespace {

struct TempDir {
  fs::path path;
  TempDir() {
    path = fs::temp_directory_path() / ("marvin_audio_test_" + std::to_string(::getpid()));
    fs::create_directories(path);
  }
  ~TempDir() { fs::remove_all(path); }
};

SoundBuffer stereo_tone(int rate, double seconds, double hz) {
  SoundBuffer sound;
  sound.sample_rate = rate;
  sound.channels = 2;
  const auto frames = static_cast<std::size_t>(rate * seconds);
  for (std::size_t i = 0; i < frames; ++i) {
    const auto v = static_cast<float>(0.5 * std::sin(2 * std::numbers::pi * hz * static_cast<double>(i) / rate));
    sound.samples.push_back(v);
    sound.samples.push_back(v);
  }
  return sound;
}

// Upward zero crossings per second: the tone's frequency.
double frequency(const std::vector<std::int16_t>& pcm, int rate) {
  int crossings = 0;
  for (std::size_t i = 1; i < pcm.size(); ++i) crossings += pcm[i - 1] < 0 && pcm[i] >= 0;
  return crossings * static_cast<double>(rate) / static_cast<double>(pcm.size());
}

}  // namespace

TEST_CASE("WAV and FLAC round trip and conversion to 16 kHz mono") {
  TempDir dir;
  const SoundBuffer sound = stereo_tone(44100, 1.0, 440.0);
  for (const char* name : {"tone.wav", "tone.flac"}) {
    CAPTURE(name);
    const fs::path file = dir.path / name;
    write_sound_file(file, sound);
    const SoundBuffer back = read_sound_file(file);
    CHECK(back.sample_rate == 44100);
    CHECK(back.channels == 2);
    REQUIRE(back.frames() == sound.frames());
    for (std::size_t i = 0; i < back.samples.size(); i += 997) {
      CHECK(back.samples[i] == doctest::Approx(sound.samples[i]).epsilon(0.001).scale(1.0));
    }
    const std::vector<std::int16_t> speech = read_speech_file(file);
    CHECK(static_cast<double>(speech.size()) == doctest::Approx(16000.0).epsilon(0.01));
    CHECK(frequency(speech, 16000) == doctest::Approx(440.0).epsilon(0.02));
  }
}

TEST_CASE("streaming resampler agrees with the one-shot conversion in length and pitch") {
  const SoundBuffer sound = stereo_tone(22050, 1.0, 300.0);
  const std::vector<float> mono = mix_to_mono(sound.samples, 2);
  StreamResampler stream(22050, 16000);
  std::vector<float> out;
  for (std::size_t pos = 0; pos < mono.size(); pos += 441) {
    stream.process(std::span<const float>(mono).subspan(pos, std::min<std::size_t>(441, mono.size() - pos)), out);
  }
  stream.flush(out);
  CHECK(static_cast<double>(out.size()) == doctest::Approx(16000.0).epsilon(0.01));
  CHECK(frequency(to_pcm16(out), 16000) == doctest::Approx(300.0).epsilon(0.02));
  CHECK_THROWS_WITH(resample(mono, 0, 16000), doctest::Contains("rates must be positive"));
}

TEST_CASE("a FLAC file with a damaged frame keeps the frames after it, the damaged one silent") {
  TempDir dir;
  // Two seconds of a tone whose loudness changes, so that no two FLAC frames are alike.
  SoundBuffer sound;
  sound.sample_rate = 16000;
  sound.channels = 1;
  for (int i = 0; i < 32000; ++i) {
    sound.samples.push_back(static_cast<float>(
        (0.2 + 0.5 * i / 32000.0) * std::sin(2.0 * std::numbers::pi * 330.0 * i / 16000.0)));
  }
  const fs::path file = dir.path / "damaged.flac";
  write_sound_file(file, sound);
  FlacDamage none;
  REQUIRE(read_sound_file(file, &none).frames() == sound.frames());
  CHECK(none.errors == 0);
  CHECK(none.silenced_frames == 0);

  // Scramble 16 bytes in the middle of the third audio frame (frames start with the sync
  // code 0xFFF8).
  std::vector<unsigned char> bytes;
  {
    std::FILE* f = std::fopen(file.c_str(), "rb");
    for (int c; (c = std::fgetc(f)) != EOF;) bytes.push_back(static_cast<unsigned char>(c));
    std::fclose(f);
  }
  std::vector<std::size_t> frame_starts;
  for (std::size_t i = 42; i + 1 < bytes.size(); ++i) {
    if (bytes[i] == 0xFF && bytes[i + 1] == 0xF8) frame_starts.push_back(i);
  }
  REQUIRE(frame_starts.size() >= 5);
  const std::size_t middle = (frame_starts[2] + frame_starts[3]) / 2;
  for (std::size_t i = middle; i < middle + 16; ++i) bytes[i] ^= 0x5A;
  {
    std::FILE* f = std::fopen(file.c_str(), "wb");
    std::fwrite(bytes.data(), 1, bytes.size(), f);
    std::fclose(f);
  }

  FlacDamage damage;
  const SoundBuffer back = read_sound_file(file, &damage);
  CHECK(damage.errors >= 1);
  REQUIRE(back.frames() == sound.frames());  // libsndfile alone stops at the damaged frame
  REQUIRE(damage.silenced_frames > 0);
  CHECK(damage.silenced_frames <= 8192);  // one frame
  REQUIRE(damage.first_frame > 0);
  const auto first = static_cast<std::size_t>(damage.first_frame);
  const auto after = first + static_cast<std::size_t>(damage.silenced_frames);
  REQUIRE(after < sound.frames());
  int wrong = 0;
  for (std::size_t i = 0; i < sound.frames(); ++i) {
    const float expected = i >= first && i < after ? 0.0f : sound.samples[i];
    wrong += std::fabs(back.samples[i] - expected) > 1e-4f ? 1 : 0;
  }
  CHECK(wrong == 0);
  // The speech path gets the same: full length, no error.
  CHECK(read_speech_file(file).size() == sound.frames());
}

TEST_CASE("a missing or broken file is reported with its name") {
  TempDir dir;
  CHECK_THROWS_WITH(read_sound_file(dir.path / "nothing.wav"), doctest::Contains("nothing.wav"));
  const fs::path junk = dir.path / "junk.wav";
  {
    std::FILE* f = std::fopen(junk.c_str(), "wb");
    std::fputs("this is not a sound file", f);
    std::fclose(f);
  }
  CHECK_THROWS_WITH(read_sound_file(junk), doctest::Contains("junk.wav"));
}

TEST_CASE("an ALSA device that does not exist fails with its name") {
  AlsaOptions options;
  options.device = "marvin_no_such_device";
  CHECK_THROWS_WITH(AlsaCapture{options}, doctest::Contains("marvin_no_such_device"));
  CHECK_THROWS_WITH(AlsaPlayback{options}, doctest::Contains("marvin_no_such_device"));
}
