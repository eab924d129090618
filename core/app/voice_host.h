// The voice front end of the host: `marvin run --sim --audio-in FILE.wav` and, with a sound
// card, `marvin run`. The same host as typed `run --sim` (skills, personal data, reminders,
// body), with a VoiceLoop (perception/voice_loop.h) where the console reader was:
//
//   microphone or recording -> wake word -> recognizer (the command grammar of the loaded
//   skills and today's contacts, voice_grammar.h) -> host.loop().post(what was heard)
//   -> the manager and the skills -> every sentence Marvin says -> espeak-ng -> speaker or
//   the output WAV, aligned with the input (voice_loop.h, "Timeline").
//
// A turn: after the end of speech the front end posts the sentence (an unrecognised one as
// "", which the manager answers with its no-match sentence, or takes as a bad answer) and
// waits until the host loop waits for the user again (HostLoop::on_waiting): what was said
// meanwhile is the reply; a kAnswer wait means a question, so the loop listens for the
// answer without the wake word, with the grammar of the slot asked for (or yes/no). What is
// said later (a long task, a reminder firing) is spoken as it comes, and a task's question
// asked later makes the loop listen for its answer. "Marvin, stop" cuts the speech and
// posts "stop", which the host loop hands to Manager::stop().
//
// Status light (red awaiting, green listening, yellow executing): the front end puts a
// body in front of the host's (Host::set_body) that shows green while listening, yellow
// while a skill acts or Marvin speaks, red otherwise; the manager's own light changes are
// merged in, so the light never turns red while Marvin is still talking.
//
// Recognition: the host's grammar is large, so the recognizer runs with
// perception::kLargeGrammarSettings and kLargeGrammarThreshold (speech_recognizer.h), and
// every sentence may start with the wake word (the detector reports its end early); the
// heard text is posted without it.
//
// Grammar changes: contacts and reminders are re-read after every turn and the grammar is
// regenerated when they changed; the skills' phrases are re-read from the registry each
// time the host loop waits for a command (the loop thread, where a skills reload also runs),
// or when rebuild_grammar() is called. Both are used from the next command on.
//
// Threads: run_recording()/run_live() run on the voice thread while host.loop().run() runs
// on another; the callbacks from the host loop only queue. Echo: live, the microphone hears
// the speaker; there is no echo cancellation yet, so the wake word may fire on Marvin's own
// "Marvin" and a loud reply can drown a barge-in.
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "app/host.h"
#include "app/voice_grammar.h"
#include "devices/audio/alsa_device.h"
#include "perception/endpointer.h"
#include "perception/speech_recognizer.h"
#include "perception/speech_synthesizer.h"
#include "perception/voice_loop.h"
#include "perception/wake_word_detector.h"

namespace marvin::app {

struct VoiceHostOptions {
  // "embedding" (speech embedding + head; the cnn spotter when setup has not fetched the
  // embedding), "cnn" = "neural" (models/marvin-kws.bin, $MARVIN_KWS_MODEL) or "pocketsphinx".
  std::string wake_word = "embedding";
  float sensitivity = 0.5f;
  std::string voice = "en-us";
  int rate_wpm = 160;
  perception::EndpointerOptions endpointer;
};

// The wake-word detector named by `kind` ("embedding", "cnn" = "neural", or "pocketsphinx";
// "embedding" falls back to the cnn spotter, with a warning naming the missing file and
// scripts/setup, when its models are not there). Throws
// std::runtime_error naming the model when it cannot be loaded.
std::unique_ptr<perception::WakeWordDetector> make_wake_word(const std::string& kind,
                                                             float sensitivity);

// The voice `base` made slower or faster, louder or quieter by `style` ("speak slower",
// skills/manager.h): 20 words per minute and a quarter of the volume per step, within what
// espeak-ng takes.
perception::SynthesisOptions styled_voice(const perception::SynthesisOptions& base,
                                          const skills::Manager::VoiceStyle& style);

class VoiceHost {
 public:
  // Call after host.load() and before host.loop().run(): loads the models, builds the
  // command grammar, and hooks into the host (on_said, on_heard, on_waiting, the body).
  // Throws std::runtime_error when a model is missing or no grammar can be built.
  VoiceHost(Host& host, const VoiceHostOptions& options);
  ~VoiceHost();  // gives the host its own body back
  VoiceHost(const VoiceHost&) = delete;
  VoiceHost& operator=(const VoiceHost&) = delete;

  // Skills changed: re-reads their phrases now. Call on a thread that may read the registry
  // (the host loop's, e.g. right after a reload; or before run()). The new grammar is used
  // from the next command on.
  void rebuild_grammar();

  // Feeds the recording through the loop (on the calling thread), then closes the host
  // loop. Returns the output, aligned with the input (silence where Marvin says nothing),
  // followed by the end of a reply still playing when the input ended.
  std::vector<std::int16_t> run_recording(std::span<const std::int16_t> input);

  // Listens to `microphone` and plays through `speaker` (sample for sample, see voice_loop.h)
  // until stop(). Throws what ALSA throws.
  void run_live(audio::AlsaCapture& microphone, audio::AlsaPlayback& speaker);
  void stop() { stopping_.store(true); }  // any thread

  // What each turn did (timing, recognition, reply), in order. After run_*() returned.
  const std::vector<perception::VoiceTurn>& turns() const { return turns_; }
  const std::string& grammar() const { return loop_->command_grammar(); }

 private:
  class StatusLight;
  using Waiting = skills::HostLoop::Waiting;

  perception::Reply respond(const perception::Recognition& recognition);
  void pump();                    // voice thread, between chunks: async speech and questions
  void refresh_grammar(bool force);  // voice thread
  std::string answer_grammar_for(const std::string& question);
  void feed(std::span<const std::int16_t> samples);
  // Voice thread: a style asked for since the last turn (taken from voice_style_), if any.
  void apply_voice_style(const std::optional<skills::Manager::VoiceStyle>& style);

  Host& host_;
  VoiceHostOptions options_;
  devices::Body& own_body_;  // the host's body before ours
  std::unique_ptr<StatusLight> light_;
  std::unique_ptr<perception::WakeWordDetector> wake_word_;
  perception::SpeechRecognizer recognizer_;
  perception::SpeechSynthesizer synthesizer_;
  std::unique_ptr<perception::VoiceLoop> loop_;
  data::PersonalData* data_ = nullptr;
  KnownWord known_;
  SlotValues values_;              // voice thread
  std::vector<perception::VoiceTurn> turns_;
  std::function<void(std::span<const std::int16_t>)> sink_;  // voice thread: where audio goes
  std::function<void()> cut_;      // voice thread: drop what the speaker has queued
  std::atomic<bool> stopping_{false};

  std::mutex mutex_;
  std::condition_variable changed_;
  std::deque<std::string> said_;          // guarded: sentences not yet spoken
  std::string last_said_;                 // guarded: the question, when one is asked
  std::uint64_t posted_ = 0;              // guarded: utterances posted by this front end
  std::uint64_t heard_ = 0;               // guarded: utterances the host loop took
  std::optional<Waiting> waiting_;        // guarded: how the loop waits since the last take
  bool question_later_ = false;           // guarded: a task asked after the turn ended
  SkillPhrases phrases_;                  // guarded
  bool phrases_changed_ = false;          // guarded
  std::optional<skills::Manager::VoiceStyle> voice_style_;  // guarded: not applied yet
};

}  // namespace marvin::app
