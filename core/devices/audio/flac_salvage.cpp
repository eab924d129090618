#include "devices/audio/flac_salvage.h"

#include <FLAC/stream_decoder.h>

#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace marvin::audio {
namespace {

struct DecoderDeleter {
  void operator()(FLAC__StreamDecoder* d) const { FLAC__stream_decoder_delete(d); }
};

struct Decoding {
  SoundBuffer sound;
  std::vector<bool> decoded;  // per sample frame: written by a good FLAC frame
  unsigned bits = 16;
  unsigned block_size = 0;  // the stream's largest block
  int errors = 0;
  // After an error libFLAC hands on the frames it could not decode as digital silence (a frame
  // whose checksum failed, the frames skipped while it searched for the next sync code).
  bool after_error = false;
};

FLAC__StreamDecoderWriteStatus on_frame(const FLAC__StreamDecoder*, const FLAC__Frame* frame,
                                        const FLAC__int32* const buffer[], void* client) {
  auto* d = static_cast<Decoding*>(client);
  const unsigned channels = frame->header.channels;
  if (d->sound.channels <= 0 || channels != static_cast<unsigned>(d->sound.channels))
    return FLAC__STREAM_DECODER_WRITE_STATUS_ABORT;
  // Where this frame's samples belong: the header carries either the first sample's number
  // or the frame's number (fixed block size; the last frame may be shorter than the others).
  const std::uint64_t first =
      frame->header.number_type == FLAC__FRAME_NUMBER_TYPE_SAMPLE_NUMBER
          ? frame->header.number.sample_number
          : static_cast<std::uint64_t>(frame->header.number.frame_number) * d->block_size;
  const std::uint64_t end = first + frame->header.blocksize;
  if (end > d->decoded.size()) {  // no or a wrong total in the stream information
    d->decoded.resize(end, false);
    d->sound.samples.resize(end * channels, 0.0f);
  }
  bool silent = true;
  for (unsigned c = 0; c < channels && silent; ++c) {
    for (unsigned i = 0; i < frame->header.blocksize && silent; ++i) silent = buffer[c][i] == 0;
  }
  const bool silenced = d->after_error && silent;
  d->after_error = silenced;
  const float scale = 1.0f / static_cast<float>(1u << (d->bits - 1));
  for (unsigned i = 0; i < frame->header.blocksize; ++i) {
    for (unsigned c = 0; c < channels; ++c) {
      d->sound.samples[(first + i) * channels + c] =
          silenced ? 0.0f : static_cast<float>(buffer[c][i]) * scale;
    }
    d->decoded[first + i] = !silenced;
  }
  return FLAC__STREAM_DECODER_WRITE_STATUS_CONTINUE;
}

void on_metadata(const FLAC__StreamDecoder*, const FLAC__StreamMetadata* m, void* client) {
  if (m->type != FLAC__METADATA_TYPE_STREAMINFO) return;
  auto* d = static_cast<Decoding*>(client);
  d->sound.sample_rate = static_cast<int>(m->data.stream_info.sample_rate);
  d->sound.channels = static_cast<int>(m->data.stream_info.channels);
  d->bits = m->data.stream_info.bits_per_sample;
  d->block_size = m->data.stream_info.max_blocksize;
  const std::uint64_t frames = m->data.stream_info.total_samples;  // 0: not known
  d->decoded.assign(frames, false);
  d->sound.samples.assign(frames * m->data.stream_info.channels, 0.0f);
}

// A damaged frame: count it. libFLAC then goes on at the next good frame, passing the
// damaged ones on as silence.
void on_error(const FLAC__StreamDecoder*, FLAC__StreamDecoderErrorStatus, void* client) {
  auto* d = static_cast<Decoding*>(client);
  ++d->errors;
  d->after_error = true;
}

}  // namespace

SoundBuffer read_flac_salvaging(const std::filesystem::path& path, FlacDamage* damage) {
  std::unique_ptr<FLAC__StreamDecoder, DecoderDeleter> decoder(FLAC__stream_decoder_new());
  if (!decoder) throw std::runtime_error("cannot read " + path.string() + ": out of memory");
  Decoding d;
  d.sound.channels = 0;
  // The MD5 check would only repeat what the frame errors say.
  FLAC__stream_decoder_set_md5_checking(decoder.get(), false);
  if (FLAC__stream_decoder_init_file(decoder.get(), path.c_str(), on_frame, on_metadata, on_error,
                                     &d) != FLAC__STREAM_DECODER_INIT_STATUS_OK) {
    throw std::runtime_error("cannot open " + path.string() + " as FLAC");
  }
  if (!FLAC__stream_decoder_process_until_end_of_metadata(decoder.get()) || d.sound.channels <= 0 ||
      d.sound.sample_rate <= 0 || d.bits < 4 || d.bits > 32) {
    throw std::runtime_error(path.string() +
                             ": unreadable FLAC stream information (expected a STREAMINFO block "
                             "with channels, rate and sample size)");
  }
  // Ends at the end of the file, or early when a frame does not fit the stream information.
  FLAC__stream_decoder_process_until_end_of_stream(decoder.get());
  FLAC__stream_decoder_finish(decoder.get());
  if (damage) {
    *damage = FlacDamage{};
    damage->errors = d.errors;
    for (std::size_t i = 0; i < d.decoded.size(); ++i) {
      if (d.decoded[i]) continue;
      if (damage->first_frame < 0) damage->first_frame = static_cast<std::int64_t>(i);
      ++damage->silenced_frames;
    }
  }
  return std::move(d.sound);
}

}  // namespace marvin::audio
