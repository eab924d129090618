// Reading a FLAC file that has damaged frames.
//
// libsndfile stops at the first FLAC frame it cannot decode (a lost sync, a bad CRC) and
// returns only the samples before it, silently: in a recording with one bad frame near the
// start the spoken word is simply gone. libFLAC itself reports the error and carries on at the
// next good frame, as audio players do. This reads the file that way: every good frame in
// place, the samples of damaged frames as silence, so the sound keeps its length and timing.
#pragma once

#include <cstdint>
#include <filesystem>

#include "devices/audio/sound_buffer.h"

namespace marvin::audio {

struct FlacDamage {
  std::int64_t silenced_frames = 0;  // sample frames (one value per channel) replaced by silence
  std::int64_t first_frame = -1;     // the first of them, -1 when none
  int errors = 0;                    // errors libFLAC reported (lost sync, bad header, CRC)
};

// Decodes `path` frame by frame. Throws std::runtime_error naming the file when it is not a
// FLAC stream at all or its stream information is unreadable.
SoundBuffer read_flac_salvaging(const std::filesystem::path& path, FlacDamage* damage);

}  // namespace marvin::audio
