#include "devices/audio/alsa_device.h"

#include <alsa/asoundlib.h>

#include <stdexcept>

namespace marvin::audio {
namespace {

// ALSA's library prints its own diagnostics to stderr ("ALSA lib confmisc.c:855: cannot find
// card '0'", several lines) before returning the error we report with the device's name:
// keep stderr to our one message.
void quiet_alsa_library(const char*, int, const char*, int, const char*, ...) {}

struct PcmHandle {
  snd_pcm_t* pcm = nullptr;
  int channels = 1;
  int sample_rate = 16000;
  int xruns = 0;

  PcmHandle(const AlsaOptions& options, snd_pcm_stream_t stream) {
    const char* what = stream == SND_PCM_STREAM_CAPTURE ? "capture" : "playback";
    static const bool quiet = [] {
      snd_lib_error_set_handler(quiet_alsa_library);
      return true;
    }();
    (void)quiet;
    int rc = snd_pcm_open(&pcm, options.device.c_str(), stream, 0);
    if (rc < 0) {
      throw std::runtime_error(std::string("cannot open ALSA ") + what + " device \"" +
                               options.device + "\": " + snd_strerror(rc));
    }
    rc = snd_pcm_set_params(pcm, SND_PCM_FORMAT_S16_LE, SND_PCM_ACCESS_RW_INTERLEAVED,
                            static_cast<unsigned>(options.channels),
                            static_cast<unsigned>(options.sample_rate), 1,
                            static_cast<unsigned>(options.buffer_ms) * 1000u);
    if (rc < 0) {
      snd_pcm_close(pcm);
      throw std::runtime_error(std::string("cannot configure ALSA ") + what + " device \"" +
                               options.device + "\" for " +
                               std::to_string(options.sample_rate) + " Hz, " +
                               std::to_string(options.channels) + " channel(s): " +
                               snd_strerror(rc));
    }
    channels = options.channels;
    sample_rate = options.sample_rate;
  }
  ~PcmHandle() { snd_pcm_close(pcm); }
};

}  // namespace

struct AlsaCapture::Impl : PcmHandle {
  using PcmHandle::PcmHandle;
};

AlsaCapture::AlsaCapture(const AlsaOptions& options)
    : impl_(std::make_unique<Impl>(options, SND_PCM_STREAM_CAPTURE)) {}
AlsaCapture::~AlsaCapture() = default;

void AlsaCapture::read(std::span<std::int16_t> out) {
  auto frames = static_cast<snd_pcm_uframes_t>(out.size() / impl_->channels);
  std::int16_t* cursor = out.data();
  while (frames > 0) {
    snd_pcm_sframes_t got = snd_pcm_readi(impl_->pcm, cursor, frames);
    if (got < 0) {
      ++impl_->xruns;
      if (snd_pcm_recover(impl_->pcm, static_cast<int>(got), 1) < 0) {
        throw std::runtime_error(std::string("ALSA capture failed: ") +
                                 snd_strerror(static_cast<int>(got)));
      }
      continue;
    }
    cursor += got * impl_->channels;
    frames -= static_cast<snd_pcm_uframes_t>(got);
  }
}

int AlsaCapture::sample_rate() const { return impl_->sample_rate; }
int AlsaCapture::overruns() const { return impl_->xruns; }

struct AlsaPlayback::Impl : PcmHandle {
  using PcmHandle::PcmHandle;
};

AlsaPlayback::AlsaPlayback(const AlsaOptions& options)
    : impl_(std::make_unique<Impl>(options, SND_PCM_STREAM_PLAYBACK)) {}

AlsaPlayback::~AlsaPlayback() { snd_pcm_drain(impl_->pcm); }

void AlsaPlayback::write(std::span<const std::int16_t> samples) {
  auto frames = static_cast<snd_pcm_uframes_t>(samples.size() / impl_->channels);
  const std::int16_t* cursor = samples.data();
  while (frames > 0) {
    snd_pcm_sframes_t put = snd_pcm_writei(impl_->pcm, cursor, frames);
    if (put < 0) {
      ++impl_->xruns;
      if (snd_pcm_recover(impl_->pcm, static_cast<int>(put), 1) < 0) {
        throw std::runtime_error(std::string("ALSA playback failed: ") +
                                 snd_strerror(static_cast<int>(put)));
      }
      continue;
    }
    cursor += put * impl_->channels;
    frames -= static_cast<snd_pcm_uframes_t>(put);
  }
}

void AlsaPlayback::stop_now() {
  snd_pcm_drop(impl_->pcm);
  snd_pcm_prepare(impl_->pcm);
}

int AlsaPlayback::sample_rate() const { return impl_->sample_rate; }
int AlsaPlayback::underruns() const { return impl_->xruns; }

}  // namespace marvin::audio
