// `marvin say "text"`: speaks through the synthesizer (checks the audio set-up).
// The voice side of `marvin run` (app/voice_run.h): a recording or the live microphone
// through the host's voice front end (app/voice_host.h).
// `marvin voice listen FILE.wav [--audio-out reply.wav]`: the voice loop (wake word,
// recognition, spoken reply) on a recording, with a small demo grammar or --grammar FILE.jsgf.
// The wake word is the embedding wake word (speech embedding + models/marvin-embedding-head.bin)
// unless --wake-word cnn (models/marvin-kws.bin) or pocketsphinx: of the three it is the one
// that hears real people (models/README.md, issue 21).
#include <atomic>
#include <csignal>
#include <cstdio>
#include <exception>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "app/cli.h"
#include "app/voice_host.h"
#include "app/voice_run.h"
#include "devices/audio/alsa_device.h"
#include "devices/audio/sound_file.h"
#include "perception/command_grammar.h"
#include "perception/speech_recognizer.h"
#include "perception/speech_synthesizer.h"
#include "perception/voice_loop.h"

namespace marvin::app {
namespace {

namespace audio = marvin::audio;
namespace perception = marvin::perception;

struct SayArgs {
  std::string text;
  std::string out;
  std::string device = "default";
  std::string voice = "en-us";
  int rate = 160;
};

perception::SpeechSynthesizer make_synthesizer(const std::string& voice, int rate) {
  perception::SynthesisOptions options;
  options.voice = voice;
  options.rate_wpm = rate;
  try {
    return perception::SpeechSynthesizer(options);
  } catch (const std::runtime_error& e) {
    throw CliError(e.what(), 2);
  }
}

void say(const SayArgs& args) {
  perception::SpeechSynthesizer synthesizer = make_synthesizer(args.voice, args.rate);
  const std::vector<std::int16_t> pcm = synthesizer.synthesize(args.text);
  if (!args.out.empty()) {
    audio::write_speech_file(args.out, pcm);
    std::printf("wrote %.2f s of speech to %s\n", static_cast<double>(pcm.size()) / 16000.0,
                args.out.c_str());
    return;
  }
  audio::AlsaOptions options;
  options.device = args.device;
  try {
    audio::AlsaPlayback speaker(options);
    speaker.write(pcm);
  } catch (const std::runtime_error& e) {
    throw CliError(std::string(e.what()) + " (no sound card? write a file with --out FILE.wav)");
  }
}

struct ListenArgs {
  std::string in;
  std::string out;
  std::string grammar;
  float sensitivity = 0.5f;
  std::string wake_word = "embedding";
  std::string voice = "en-us";
  int rate = 160;
};

std::unique_ptr<perception::WakeWordDetector> make_wake_word(const ListenArgs& args) {
  try {
    return app::make_wake_word(args.wake_word, args.sensitivity);
  } catch (const std::exception& e) {
    throw CliError(e.what(), 2);
  }
}

// A few everyday commands, for trying the loop without skills.
std::vector<perception::GrammarIntent> demo_intents() {
  using perception::SlotKind;
  return {
      {"time", {"what time is it", "what's the time", "tell me the time"}, {}},
      {"call", {"(call|phone|ring) {contact}"}, {{"contact", SlotKind::kPhrases, {"anna", "bob"}}}},
      {"lights", {"(turn|switch) (on|off) [the] {device}"},
       {{"device", SlotKind::kPhrases, {"lamp", "fan", "radio", "kitchen light"}}}},
      {"timer", {"set [a] timer for {duration}"}, {{"duration", SlotKind::kDuration, {}}}},
      {"reminder", {"remind me to {task} {when}"},
       {{"task", SlotKind::kText, {}}, {"when", SlotKind::kDateTime, {}}}},
  };
}

void listen(const ListenArgs& args) {
  std::vector<std::int16_t> input;
  try {
    input = audio::read_speech_file(args.in);
  } catch (const std::runtime_error& e) {
    throw CliError(e.what(), 2);
  }
  perception::SpeechSynthesizer synthesizer = make_synthesizer(args.voice, args.rate);
  std::unique_ptr<perception::WakeWordDetector> wake_word_ptr = make_wake_word(args);
  perception::WakeWordDetector& wake_word = *wake_word_ptr;
  perception::SpeechRecognizer recognizer;
  std::string jsgf;
  if (!args.grammar.empty()) {
    std::ifstream file(args.grammar);
    if (!file) throw CliError("cannot read grammar " + args.grammar, 2);
    std::ostringstream text;
    text << file.rdbuf();
    jsgf = text.str();
  } else {
    const std::vector<perception::GrammarIntent> intents = demo_intents();
    jsgf = perception::build_command_grammar(intents, {}, [&](std::string_view w) {
             return recognizer.knows_word(w);
           }).jsgf;
  }
  try {
    recognizer.set_grammar(jsgf);
  } catch (const std::runtime_error& e) {
    throw CliError(args.grammar + ": " + e.what(), 2);
  }

  std::vector<std::int16_t> reply_audio;
  perception::VoiceLoop loop(
      wake_word, recognizer, synthesizer,
      [](const perception::Recognition& r) {
        return perception::Reply{r.matched ? "You said: " + r.text : "Sorry, I did not understand.",
                                 false, {}};
      },
      [&](std::span<const std::int16_t> chunk) {
        reply_audio.insert(reply_audio.end(), chunk.begin(), chunk.end());
      });
  loop.on_state([](perception::VoiceState s) {
    static const char* const kLight[] = {"red", "green", "yellow"};
    std::printf("[light: %s (%s)]\n", kLight[static_cast<int>(s)], perception::to_string(s));
  });
  loop.on_turn([](const perception::VoiceTurn& t) {
    if (t.wake_sample >= 0) std::printf("wake word at %.2f s\n", static_cast<double>(t.wake_sample) / 16000.0);
    if (t.timed_out) {
      std::printf("nothing said\n");
    } else if (t.recognition.matched) {
      std::printf("heard: %s (confidence %.1f)\n", t.recognition.text.c_str(), t.recognition.confidence);
    } else {
      std::printf("no match: %s\n", t.recognition.reason.c_str());
    }
    if (!t.reply.text.empty()) std::printf("Marvin: %s\n", t.reply.text.c_str());
  });
  for (std::size_t pos = 0; pos < input.size(); pos += 320) {
    loop.feed(std::span<const std::int16_t>(input).subspan(pos, std::min<std::size_t>(320, input.size() - pos)));
  }
  loop.finish();
  if (!args.out.empty()) {
    audio::write_speech_file(args.out, reply_audio);
    std::printf("wrote %.2f s of replies to %s\n", static_cast<double>(reply_audio.size()) / 16000.0,
                args.out.c_str());
  }
}

void install_voice_commands(CLI::App& root) {
  auto say_args = std::make_shared<SayArgs>();
  CLI::App* say_cmd = root.add_subcommand("say", "Speak a sentence through the speech synthesizer");
  say_cmd->add_option("text", say_args->text, "What to say")->required();
  say_cmd->add_option("--out", say_args->out, "Write a 16 kHz WAV file instead of playing");
  say_cmd->add_option("--device", say_args->device, "ALSA playback device")->capture_default_str();
  say_cmd->add_option("--voice", say_args->voice, "espeak-ng voice")->capture_default_str();
  say_cmd->add_option("--rate", say_args->rate, "Words per minute (80..450)")->capture_default_str();
  say_cmd->callback([say_args] { say(*say_args); });

  CLI::App& voice = command_group(root, "voice", "The voice loop: wake word, recognition, speech");
  auto listen_args = std::make_shared<ListenArgs>();
  CLI::App* listen_cmd = voice.add_subcommand("listen", "Run the voice loop on a recording");
  listen_cmd->add_option("file", listen_args->in, "Recording (WAV, FLAC, any rate)")->required();
  listen_cmd->add_option("--audio-out", listen_args->out, "Write the spoken replies to this WAV");
  listen_cmd->add_option("--grammar", listen_args->grammar, "JSGF grammar (default: a demo set)");
  listen_cmd->add_option("--sensitivity", listen_args->sensitivity, "Wake word sensitivity 0..1")
      ->capture_default_str();
  listen_cmd->add_option("--wake-word", listen_args->wake_word,
                         "Wake-word detector: embedding (the default: speech embedding + "
                         "models/marvin-embedding-head.bin; falls back to cnn without "
                         "scripts/setup's models), cnn or neural (models/marvin-kws.bin or "
                         "$MARVIN_KWS_MODEL), or pocketsphinx keyphrase spotting")
      ->check(CLI::IsMember({"embedding", "cnn", "neural", "pocketsphinx"}))
      ->capture_default_str();
  listen_cmd->add_option("--voice", listen_args->voice, "espeak-ng voice")->capture_default_str();
  listen_cmd->add_option("--rate", listen_args->rate, "Words per minute")->capture_default_str();
  listen_cmd->callback([listen_args] { listen(*listen_args); });
}

}  // namespace

MARVIN_CLI_COMMANDS(install_voice_commands);

// ---- the voice side of `marvin run` (voice_run.h) ----------------------------------------

void add_voice_run_options(CLI::App& run, VoiceRunOptions& o) {
  CLI::Option* in = run.add_option(
      "--audio-in", o.audio_in,
      "With --sim: hear this recording (WAV, FLAC, any rate) instead of typed requests");
  run.add_option("--audio-out", o.audio_out,
                 "With --audio-in: write Marvin's speech to this WAV, aligned with the recording")
      ->needs(in);
  run.add_option("--wake-word", o.wake_word,
                 "Wake-word detector: embedding (the default: speech embedding + "
                 "models/marvin-embedding-head.bin; falls back to cnn without "
                 "scripts/setup's models), cnn or neural (models/marvin-kws.bin or "
                 "$MARVIN_KWS_MODEL), or pocketsphinx keyphrase spotting")
      ->check(CLI::IsMember({"embedding", "cnn", "neural", "pocketsphinx"}))
      ->capture_default_str();
  run.add_option("--sensitivity", o.sensitivity, "Wake word sensitivity 0..1")
      ->capture_default_str();
  run.add_option("--audio-device", o.device,
                 "Without --sim: the ALSA device of the microphone and speaker")
      ->capture_default_str();
}

struct LiveAudio {
  std::unique_ptr<audio::AlsaCapture> microphone;
  std::unique_ptr<audio::AlsaPlayback> speaker;
};

std::shared_ptr<LiveAudio> open_live_audio(const VoiceRunOptions& o) {
  audio::AlsaOptions options;
  options.device = o.device;
  auto live = std::make_shared<LiveAudio>();
  const char* hint =
      " (no sound card? `marvin run --sim` takes typed requests, `marvin run --sim "
      "--audio-in FILE.wav` a recording; or choose the device with --audio-device)";
  try {
    live->microphone = std::make_unique<audio::AlsaCapture>(options);
  } catch (const std::exception& e) {
    throw CliError(std::string("no microphone: ") + e.what() + hint, 1);
  }
  try {
    live->speaker = std::make_unique<audio::AlsaPlayback>(options);
  } catch (const std::exception& e) {
    throw CliError(std::string("no speaker: ") + e.what() + hint, 1);
  }
  return live;
}

void run_voice(std::unique_ptr<Host> host_ptr, const VoiceRunOptions& o,
               const std::shared_ptr<LiveAudio>& live, ShutdownSignals& signals,
               std::shared_ptr<void> page) {
  // A local goes before the parameters on every way out (also a throw): the page, which
  // calls into the host, stops before the host is destroyed.
  std::shared_ptr<void> serving = std::move(page);
  Host& host = *host_ptr;
  std::vector<std::int16_t> input;
  if (!live) {
    try {
      input = audio::read_speech_file(o.audio_in);
    } catch (const std::exception& e) {
      throw CliError(std::string("--audio-in: ") + e.what(), 2);
    }
  }
  VoiceHostOptions options;
  options.wake_word = o.wake_word;
  options.sensitivity = o.sensitivity;
  std::unique_ptr<VoiceHost> voice;
  try {
    voice = std::make_unique<VoiceHost>(host, options);
  } catch (const std::exception& e) {
    throw CliError(std::string("cannot start the voice loop: ") + e.what(), 2);
  }
  host.body().set_light(devices::Light::kAwaiting);
  host.manager().say("Hello, I'm Marvin.");
  host.start_scheduler();
  if (live) {
    host.show("Marvin is listening on \"" + o.device + "\". Say \"Marvin\", then your request; "
              "Ctrl-C quits.");
  }
  signals.on_signal([&host, voice = voice.get()](int signal) {
    host.show(std::string("[") + signal_name(signal) + ": stopping]");
    voice->stop();
    host.loop().shut_down();
  });
  // The voice thread stands where the console reader stands in typed mode.
  std::vector<std::int16_t> output;
  std::exception_ptr failure;
  std::thread listener([&] {
    try {
      if (live) {
        voice->run_live(*live->microphone, *live->speaker);
      } else {
        output = voice->run_recording(input);
      }
    } catch (...) {
      failure = std::current_exception();
      host.loop().close();
    }
  });
  host.loop().run();
  listener.join();
  signals.on_signal({});  // the handler uses the host and the voice, which go below
  serving.reset();   // the web page calls into the host: it stops first
  host_ptr.reset();  // first: a task or the scheduler may still be talking to the front end
  voice.reset();
  if (failure) {
    try {
      std::rethrow_exception(failure);
    } catch (const std::exception& e) {
      throw CliError(std::string("voice loop: ") + e.what(), 1);
    }
  }
  if (!o.audio_out.empty()) {
    try {
      audio::write_speech_file(o.audio_out, output);
    } catch (const std::exception& e) {
      throw CliError(std::string("--audio-out: ") + e.what(), 1);
    }
    std::printf("wrote %.2f s of audio to %s (aligned with %s)\n",
                static_cast<double>(output.size()) / 16000.0, o.audio_out.c_str(),
                o.audio_in.c_str());
  }
}

}  // namespace marvin::app
