// The voice loop without the graph: wake word -> listen -> recognise -> answer -> speak.
//
// A VoiceLoop is fed the microphone (or a recording) in chunks of any size and drives:
//
//   kAwaiting   (status light red)    the wake-word detector hears everything;
//   kListening  (green)               after the wake word (or a question the robot asked):
//                                     audio goes to the recognizer until the endpointer hears
//                                     the end of speech, or its timeout;
//   kExecuting  (yellow)              the recognised sentence (or "no match") goes to the
//                                     responder; its reply is synthesised and then plays
//                                     (see "Timeline"); then back to kAwaiting, or kListening
//                                     when the reply expects an answer.
//
// Everything happens synchronously inside feed(), on the caller's thread. The graph version
// (issue 2's Latch between wake word and recognizer) splits the same parts into nodes.
//
// Timeline. Time is the input stream: sample i of the output belongs to sample i of the
// input. A reply starts playing at the sample where the endpointer decided (the responder
// and the synthesis take no stream time: on a recording they are free, live the speaker
// runs that much behind) and plays for its length while the input keeps being processed:
//   - during playback the wake-word detector listens (state kExecuting). The wake word cuts
//     the reply where it was detected (barge-in: the robot stops talking to listen, and a
//     real microphone would otherwise hear its own voice over the command); the cut reply
//     is not resumed, on_barge_in() is told, and the command after it is heard as usual.
//     "Marvin, stop" therefore silences the reply at "marvin", and the responder gets
//     "stop" (the host stops the running task);
//   - a reply that expects an answer is a question: listening for the answer starts when
//     the question has finished playing (a person answers after the question), without
//     the wake word, with the reply's answer grammar;
//   - say() queues more speech (a long task's progress, a reminder that fired) behind what
//     is playing; it plays whenever the loop is not listening.
// With VoiceLoopOptions::aligned_output the sink receives one output sample for every input
// sample (reply audio or silence), plus what is still playing at finish(): written to a WAV
// it lines up with the recording. Without it, the sink receives only the reply samples,
// each as its time comes (the rest of a reply at finish()).
//
// The command starts where the wake word ended, not where the detector became sure of it: a
// detector may report a keyword some steps after its end (the embedding wake word at a low
// sensitivity), and "Marvin, stop" said in one breath would otherwise reach the recognizer as
// "-op". The loop keeps the last kMaxPreRollSamples of what it heard while awaiting and starts
// the endpointer and the recognizer at the detection's end_sample.
//
// A question that gets no answer (the endpointer times out) is answered with an empty,
// unmatched Recognition whose reason is "nothing said", so the asker can ask again or give
// up; after the wake word, silence just returns to kAwaiting.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "perception/endpointer.h"
#include "perception/speech_recognizer.h"
#include "perception/speech_synthesizer.h"
#include "perception/wake_word_detector.h"

namespace marvin::perception {

enum class VoiceState { kAwaiting, kListening, kExecuting };

// "awaiting", "listening", "executing".
const char* to_string(VoiceState state);

struct Reply {
  std::string text;             // spoken; empty says nothing
  bool expects_answer = false;  // listen after speaking, no wake word needed
  // With expects_answer: the JSGF grammar for the answer (e.g. build_command_grammar of one
  // intent "[it's|to|for] {slot}" plus the conversation phrases); empty keeps the command
  // grammar. The command grammar is restored after the answer.
  std::string answer_grammar;
};

// One command, for logs and benchmarks. Samples count from the first sample fed.
struct VoiceTurn {
  std::int64_t wake_sample = -1;          // end of the wake word (-1: follow-up answer)
  std::int64_t speech_begin_sample = 0;
  std::int64_t speech_end_sample = 0;     // last speech heard by the endpointer
  std::int64_t endpoint_sample = 0;       // where the endpointer decided (after the silence)
  bool timed_out = false;                 // nothing was said
  Recognition recognition;
  Reply reply;
  // Computation from the endpoint decision until the reply is ready to play (recognizer
  // finish + responder + synthesis of the whole reply), measured by the loop: on a live
  // device, the time the speaker runs behind the stream.
  std::chrono::nanoseconds compute_to_first_audio{0};
  std::int64_t reply_samples = 0;         // length of the synthesised reply
};

struct VoiceLoopOptions {
  EndpointerOptions endpointer;
  bool aligned_output = false;  // see "Timeline" above
};

class VoiceLoop {
 public:
  // How far back before a detection the command may start (0.5 s).
  static constexpr std::size_t kMaxPreRollSamples = 8000;

  using Responder = std::function<Reply(const Recognition&)>;
  using AudioSink = std::function<void(std::span<const std::int16_t>)>;

  // The parts are borrowed and must outlive the loop; the recognizer must have a grammar,
  // which becomes the command grammar.
  VoiceLoop(WakeWordDetector& wake_word, SpeechRecognizer& recognizer,
            SpeechSynthesizer& synthesizer, Responder responder, AudioSink sink,
            const VoiceLoopOptions& options = {});

  // Called on every state change, with the new state (drive the status light from here).
  void on_state(std::function<void(VoiceState)> listener) { state_listener_ = std::move(listener); }
  // Called at the end of each turn, when the reply has been synthesised (before it plays).
  void on_turn(std::function<void(const VoiceTurn&)> listener) { turn_listener_ = std::move(listener); }
  // Called when the wake word cut speech short, with the stream sample of the cut.
  void on_barge_in(std::function<void(std::int64_t)> listener) { barge_in_listener_ = std::move(listener); }

  // 16 kHz mono PCM16, any chunk size.
  void feed(std::span<const std::int16_t> samples);

  // Ends a command in progress as if silence followed (end of a recording) and delivers
  // the rest of the speech queued to the sink.
  void finish();

  // Queues `text` to be spoken after what is playing (see "Timeline"). Empty is ignored.
  void say(const std::string& text);
  // The host asked a question on its own (a long task's ask()): listen for the answer once
  // the speech queued now has played, with `answer_grammar` ("" = the command grammar).
  // Ignored while listening: what is being said goes to the question anyway.
  void expect_answer(const std::string& answer_grammar);
  // Replaces the command grammar (skills or contacts changed); used from the next command
  // on, never inside an utterance. Checked only when it is used (feed() then throws the
  // recognizer's std::runtime_error): build it with build_command_grammar().
  void set_command_grammar(std::string jsgf) { command_grammar_ = std::move(jsgf); }
  const std::string& command_grammar() const { return command_grammar_; }

  VoiceState state() const { return state_; }
  bool speaking() const { return played_ < playback_.size(); }
  std::int64_t samples_fed() const { return samples_; }

 private:
  void set_state(VoiceState state);
  // Starts a turn; `pre_roll` is audio already heard that belongs to the command.
  void start_listening(std::int64_t wake_sample, std::span<const std::int16_t> pre_roll = {});
  void remember(std::span<const std::int16_t> heard);  // keeps the pre-roll candidates
  void complete_turn(bool timed_out, std::chrono::steady_clock::time_point decided);
  void queue_speech(const std::string& text);
  void after_speech();                 // playback over: listen for an answer, or await
  void emit(std::size_t n);            // n output samples at the current stream position
  void reset_wake_word();

  WakeWordDetector& wake_word_;
  SpeechRecognizer& recognizer_;
  SpeechSynthesizer& synthesizer_;
  Responder responder_;
  AudioSink sink_;
  VoiceLoopOptions options_;
  Endpointer endpointer_;
  std::function<void(VoiceState)> state_listener_;
  std::function<void(const VoiceTurn&)> turn_listener_;
  std::function<void(std::int64_t)> barge_in_listener_;
  VoiceState state_ = VoiceState::kAwaiting;
  std::int64_t samples_ = 0;
  std::int64_t wake_word_base_ = 0;  // stream sample where the detector's numbering starts
  std::int64_t listen_start_ = 0;
  VoiceTurn turn_;
  std::string command_grammar_;
  bool answer_expected_ = false;     // listen without the wake word after the speech
  bool finishing_ = false;           // inside finish()
  std::string answer_grammar_;
  std::vector<std::int16_t> playback_;  // speech queued; [played_, size) still to play
  // The latest audio heard while awaiting or speaking, ending at samples_ (at most twice
  // kMaxPreRollSamples, so that trimming it is rare).
  std::vector<std::int16_t> recent_;
  std::size_t played_ = 0;
  std::vector<std::int16_t> silence_;
  std::vector<WakeWordDetection> detections_;
};

}  // namespace marvin::perception
