// The voice loop without the graph: wake word -> listen -> recognise -> answer -> speak.
//
// A VoiceLoop is fed the microphone (or a recording) in chunks of any size and drives:
//
//   kAwaiting   (status light red)    the wake-word detector hears everything;
//   kListening  (green)               after the wake word (or a question the robot asked):
//                                     audio goes to the recognizer until the endpointer hears
//                                     the end of speech, or its timeout;
//   kExecuting  (yellow)              the recognised sentence (or "no match") goes to the
//                                     responder, whose reply is spoken through the sink;
//                                     then back to kAwaiting (or kListening for an answer).
//
// Everything happens synchronously inside feed(), on the caller's thread: audio fed while
// executing is the audio after the command, processed when feed() continues. The graph
// version (issue 2's Latch between wake word and recognizer) splits the same parts into
// nodes.
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
  bool expects_answer = false;  // listen again right after speaking (no wake word needed)
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
  // Computation time from the endpoint decision to the first reply sample handed to the sink
  // (recognizer finish + responder + synthesis of the first chunk), measured by the loop.
  std::chrono::nanoseconds compute_to_first_audio{0};
  bool reply_interrupted = false;
};

struct VoiceLoopOptions {
  EndpointerOptions endpointer;
};

class VoiceLoop {
 public:
  using Responder = std::function<Reply(const Recognition&)>;
  using AudioSink = std::function<void(std::span<const std::int16_t>)>;

  // The parts are borrowed and must outlive the loop; the recognizer must have a grammar.
  VoiceLoop(WakeWordDetector& wake_word, SpeechRecognizer& recognizer,
            SpeechSynthesizer& synthesizer, Responder responder, AudioSink sink,
            const VoiceLoopOptions& options = {});

  // Called on every state change, with the new state (drive the status light from here).
  void on_state(std::function<void(VoiceState)> listener) { state_listener_ = std::move(listener); }
  // Called at the end of each turn.
  void on_turn(std::function<void(const VoiceTurn&)> listener) { turn_listener_ = std::move(listener); }

  // 16 kHz mono PCM16, any chunk size.
  void feed(std::span<const std::int16_t> samples);

  // Ends a command in progress as if silence followed (end of a recording).
  void finish();

  VoiceState state() const { return state_; }
  std::int64_t samples_fed() const { return samples_; }

 private:
  void set_state(VoiceState state);
  void start_listening(std::int64_t wake_sample);
  void complete_turn(bool timed_out, std::chrono::steady_clock::time_point decided);

  WakeWordDetector& wake_word_;
  SpeechRecognizer& recognizer_;
  SpeechSynthesizer& synthesizer_;
  Responder responder_;
  AudioSink sink_;
  Endpointer endpointer_;
  std::function<void(VoiceState)> state_listener_;
  std::function<void(const VoiceTurn&)> turn_listener_;
  VoiceState state_ = VoiceState::kAwaiting;
  std::int64_t samples_ = 0;
  std::int64_t wake_word_base_ = 0;  // stream sample where the detector's numbering starts
  std::int64_t listen_start_ = 0;
  VoiceTurn turn_;
  std::string command_grammar_;  // saved while an answer grammar is in use
  std::vector<WakeWordDetection> detections_;
};

}  // namespace marvin::perception
