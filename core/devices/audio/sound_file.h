// Reading and writing sound files through libsndfile (WAV, FLAC, and whatever else the
// installed libsndfile reads).
//
// Errors throw std::runtime_error naming the file and what libsndfile said.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <vector>

#include "devices/audio/flac_salvage.h"
#include "devices/audio/sound_buffer.h"

namespace marvin::audio {

// Reads the whole file. Any format libsndfile knows; samples converted to float. A FLAC file
// with damaged frames, which libsndfile would cut short at the first of them, is decoded
// again frame by frame (flac_salvage.h): its damaged frames become silence and `damage`, when
// given, says how much (otherwise it is left at no damage).
SoundBuffer read_sound_file(const std::filesystem::path& path, FlacDamage* damage = nullptr);

// Reads the file and converts it to the speech format: mono (channels averaged), 16 kHz
// (resampled with libsoxr), 16-bit PCM. `damage` as for read_sound_file, in the file's frames.
std::vector<std::int16_t> read_speech_file(const std::filesystem::path& path,
                                           FlacDamage* damage = nullptr);

// Writes 16-bit PCM; the container follows the extension: ".flac" -> FLAC, anything else ->
// WAV. Overwrites an existing file.
void write_sound_file(const std::filesystem::path& path, const SoundBuffer& sound);

// Writes 16 kHz mono 16-bit PCM (the speech format).
void write_speech_file(const std::filesystem::path& path, std::span<const std::int16_t> pcm,
                       int sample_rate = kSpeechSampleRate);

}  // namespace marvin::audio
