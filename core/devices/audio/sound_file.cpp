#include "devices/audio/sound_file.h"

#include <sndfile.h>

#include <memory>
#include <stdexcept>
#include <string>

#include "devices/audio/resampler.h"

namespace marvin::audio {
namespace {

struct SndfileCloser {
  void operator()(SNDFILE* file) const { sf_close(file); }
};
using SndfilePtr = std::unique_ptr<SNDFILE, SndfileCloser>;

std::string lower_extension(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  for (char& c : ext) {
    if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
  }
  return ext;
}

}  // namespace

SoundBuffer read_sound_file(const std::filesystem::path& path, FlacDamage* damage) {
  if (damage) *damage = FlacDamage{};
  SF_INFO info{};
  SndfilePtr file(sf_open(path.c_str(), SFM_READ, &info));
  if (!file) {
    throw std::runtime_error("cannot read sound file " + path.string() + ": " +
                             sf_strerror(nullptr));
  }
  if (info.channels <= 0 || info.samplerate <= 0) {
    throw std::runtime_error("sound file " + path.string() + " has no channels or no rate");
  }
  SoundBuffer sound;
  sound.sample_rate = info.samplerate;
  sound.channels = info.channels;
  sound.samples.resize(static_cast<std::size_t>(info.frames) * info.channels);
  const sf_count_t got = sf_readf_float(file.get(), sound.samples.data(), info.frames);
  if (got < info.frames && (info.format & SF_FORMAT_TYPEMASK) == SF_FORMAT_FLAC)
    return read_flac_salvaging(path, damage);
  if (got < 0) throw std::runtime_error("cannot read samples of " + path.string());
  sound.samples.resize(static_cast<std::size_t>(got) * info.channels);
  return sound;
}

std::vector<std::int16_t> read_speech_file(const std::filesystem::path& path, FlacDamage* damage) {
  return to_pcm16(to_speech_format(read_sound_file(path, damage)));
}

void write_sound_file(const std::filesystem::path& path, const SoundBuffer& sound) {
  if (sound.channels <= 0 || sound.sample_rate <= 0) {
    throw std::runtime_error("cannot write " + path.string() +
                             ": sound needs a positive rate and channel count");
  }
  SF_INFO info{};
  info.samplerate = sound.sample_rate;
  info.channels = sound.channels;
  info.format = (lower_extension(path) == ".flac" ? SF_FORMAT_FLAC : SF_FORMAT_WAV) |
                SF_FORMAT_PCM_16;
  SndfilePtr file(sf_open(path.c_str(), SFM_WRITE, &info));
  if (!file) {
    throw std::runtime_error("cannot write sound file " + path.string() + ": " +
                             sf_strerror(nullptr));
  }
  // Clip rather than wrap samples outside [-1, 1].
  sf_command(file.get(), SFC_SET_CLIPPING, nullptr, SF_TRUE);
  const auto frames = static_cast<sf_count_t>(sound.frames());
  if (sf_writef_float(file.get(), sound.samples.data(), frames) != frames) {
    throw std::runtime_error("cannot write samples to " + path.string() + ": " +
                             sf_strerror(file.get()));
  }
}

void write_speech_file(const std::filesystem::path& path, std::span<const std::int16_t> pcm,
                       int sample_rate) {
  SoundBuffer sound;
  sound.sample_rate = sample_rate;
  sound.channels = 1;
  sound.samples = to_float(pcm);
  write_sound_file(path, sound);
}

}  // namespace marvin::audio
