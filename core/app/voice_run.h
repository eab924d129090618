// The voice side of `marvin run` (implemented in cli_voice.cpp, used by cli_skills.cpp):
//   marvin run --sim --audio-in FILE.wav [--audio-out reply.wav]   a recording
//   marvin run                                                      microphone and speaker
// Both run the host with the voice front end of app/voice_host.h.
#pragma once

#include <memory>
#include <string>

#include "app/cli.h"
#include "app/host.h"
#include "app/shutdown_signals.h"

namespace marvin::app {

struct VoiceRunOptions {
  std::string audio_in;   // a recording (WAV, FLAC, any rate): run on it, then quit
  std::string audio_out;  // with audio_in: Marvin's speech, aligned with the recording
  std::string wake_word = "embedding";  // or "cnn", "pocketsphinx", as `marvin voice listen`
  float sensitivity = 0.5f;
  std::string device = "default";  // ALSA device for the live microphone and speaker
};

void add_voice_run_options(CLI::App& run, VoiceRunOptions& options);

// The live microphone and speaker. Opened before the host so a machine without a sound
// card fails at once with a CliError naming the device and suggesting --sim.
struct LiveAudio;
std::shared_ptr<LiveAudio> open_live_audio(const VoiceRunOptions& options);

// Runs `host` (loaded, nothing started yet) with the voice front end on the recording, or on
// `live` when given, until the recording ends (live: until SIGINT or SIGTERM, which stop
// a recording early too; `signals` was constructed before the host). Destroys the host before
// the front end (the host's threads talk to it until they are gone), then writes
// --audio-out. Throws CliError on a bad recording or missing speech models. `page` (the web
// page serving this host, or null) is released first, before the host.
void run_voice(std::unique_ptr<Host> host, const VoiceRunOptions& options,
               const std::shared_ptr<LiveAudio>& live, ShutdownSignals& signals,
               std::shared_ptr<void> page = {});

}  // namespace marvin::app
