#include "perception/speech_synthesizer.h"

#include <espeak-ng/speak_lib.h>

#include <exception>
#include <mutex>
#include <stdexcept>

#include "devices/audio/resampler.h"
#include "devices/audio/sound_buffer.h"

namespace marvin::perception {
namespace {

std::mutex& engine_mutex() {
  static std::mutex mutex;
  return mutex;
}

// The engine's native rate, after the one-time initialisation (under engine_mutex()).
int engine_rate() {
  static int rate = 0;
  if (rate == 0) {
    const int r = espeak_Initialize(AUDIO_OUTPUT_SYNCHRONOUS, 20, nullptr, 0);
    if (r <= 0) {
      throw std::runtime_error("espeak-ng: cannot initialise (is the espeak-ng-data package "
                               "installed?)");
    }
    rate = r;
  }
  return rate;
}

struct SpeakContext {
  const std::function<void(std::span<const std::int16_t>)>* sink = nullptr;
  std::atomic<bool>* interrupted = nullptr;
  audio::StreamResampler* resampler = nullptr;
  std::vector<float> in;
  std::vector<float> out;
  std::vector<std::int16_t> pcm;
  std::exception_ptr error;
  bool stopped = false;

  void deliver() {
    if (out.empty()) return;
    pcm.resize(out.size());
    audio::float_to_pcm16(out, pcm);
    out.clear();
    (*sink)(pcm);
  }
};

int on_synth(short* wav, int count, espeak_EVENT* events) {
  auto* ctx = static_cast<SpeakContext*>(events->user_data);
  if (ctx == nullptr || ctx->stopped) return 1;
  if (ctx->interrupted->load()) {
    ctx->stopped = true;
    return 1;
  }
  if (wav == nullptr || count <= 0) return 0;
  try {
    ctx->in.resize(static_cast<std::size_t>(count));
    for (int i = 0; i < count; ++i) ctx->in[static_cast<std::size_t>(i)] = static_cast<float>(wav[i]) / 32768.0f;
    ctx->resampler->process(ctx->in, ctx->out);
    ctx->deliver();
  } catch (...) {
    ctx->error = std::current_exception();
    ctx->stopped = true;
    return 1;
  }
  return 0;
}

void apply(const SynthesisOptions& options) {
  if (espeak_SetVoiceByName(options.voice.c_str()) != EE_OK) {
    throw std::runtime_error("espeak-ng: unknown voice \"" + options.voice + "\"");
  }
  espeak_SetParameter(espeakRATE, options.rate_wpm, 0);
  espeak_SetParameter(espeakPITCH, options.pitch, 0);
  espeak_SetParameter(espeakVOLUME, options.volume, 0);
}

}  // namespace

SpeechSynthesizer::SpeechSynthesizer(const SynthesisOptions& options) { set_options(options); }

void SpeechSynthesizer::set_options(const SynthesisOptions& options) {
  if (options.rate_wpm < espeakRATE_MINIMUM || options.rate_wpm > espeakRATE_MAXIMUM) {
    throw std::runtime_error("SynthesisOptions.rate_wpm must be in 80..450, got " +
                             std::to_string(options.rate_wpm));
  }
  if (options.pitch < 0 || options.pitch > 100) {
    throw std::runtime_error("SynthesisOptions.pitch must be in 0..100");
  }
  if (options.volume < 0 || options.volume > 200) {
    throw std::runtime_error("SynthesisOptions.volume must be in 0..200");
  }
  std::lock_guard lock(engine_mutex());
  engine_rate();
  apply(options);  // validates the voice
  options_ = options;
}

bool SpeechSynthesizer::speak(std::string_view text,
                              const std::function<void(std::span<const std::int16_t>)>& sink) {
  std::lock_guard lock(engine_mutex());
  interrupted_.store(false);
  audio::StreamResampler resampler(engine_rate(), kSampleRate);
  apply(options_);
  SpeakContext ctx;
  ctx.sink = &sink;
  ctx.interrupted = &interrupted_;
  ctx.resampler = &resampler;
  espeak_SetSynthCallback(on_synth);
  const std::string buffer(text);
  const espeak_ERROR rc = espeak_Synth(buffer.c_str(), buffer.size() + 1, 0, POS_CHARACTER, 0,
                                       espeakCHARS_UTF8, nullptr, &ctx);
  if (ctx.error) std::rethrow_exception(ctx.error);
  if (ctx.stopped) {
    espeak_Cancel();
    return false;
  }
  if (rc != EE_OK) throw std::runtime_error("espeak-ng: synthesis failed");
  resampler.flush(ctx.out);
  ctx.deliver();
  return true;
}

std::vector<std::int16_t> SpeechSynthesizer::synthesize(std::string_view text) {
  std::vector<std::int16_t> all;
  speak(text, [&](std::span<const std::int16_t> chunk) { all.insert(all.end(), chunk.begin(), chunk.end()); });
  return all;
}

}  // namespace marvin::perception
