// Live sound through ALSA: a microphone to read from and a speaker to write to.
//
// Both open the named PCM device ("default", "hw:1,0", "plughw:0", ...) for 16-bit
// interleaved samples at the requested rate (ALSA's plug layer converts when the card
// cannot). A machine without a sound card fails at construction with a runtime_error naming
// the device and ALSA's reason, so callers can fall back to files.
//
// Not thread-safe: each object is used by one thread at a time (the audio source or sink
// node that owns it).
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string>

namespace marvin::audio {

struct AlsaOptions {
  std::string device = "default";
  int sample_rate = 16000;
  int channels = 1;
  int period_ms = 10;  // the chunk size ALSA wakes us with
  int buffer_ms = 80;  // total device buffer; larger survives scheduling hiccups, adds delay
};

class AlsaCapture {
 public:
  // Opens and starts the capture device. Throws std::runtime_error on failure.
  explicit AlsaCapture(const AlsaOptions& options = {});
  ~AlsaCapture();
  AlsaCapture(const AlsaCapture&) = delete;
  AlsaCapture& operator=(const AlsaCapture&) = delete;

  // Blocks until `out.size() / channels` frames are read. Recovers from an overrun
  // (counted in overruns(); the missing audio is lost). Throws on an unrecoverable error.
  void read(std::span<std::int16_t> out);

  int sample_rate() const;
  int overruns() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

class AlsaPlayback {
 public:
  explicit AlsaPlayback(const AlsaOptions& options = {});
  ~AlsaPlayback();  // drains what was written
  AlsaPlayback(const AlsaPlayback&) = delete;
  AlsaPlayback& operator=(const AlsaPlayback&) = delete;

  // Blocks until the samples are queued. Recovers from an underrun (counted).
  void write(std::span<const std::int16_t> samples);
  // Drops what is queued but not yet played (used when speech is interrupted).
  void stop_now();

  int sample_rate() const;
  int underruns() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace marvin::audio
