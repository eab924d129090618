#include "perception/voice_loop.h"

#include <algorithm>

namespace marvin::perception {

const char* to_string(VoiceState state) {
  switch (state) {
    case VoiceState::kAwaiting: return "awaiting";
    case VoiceState::kListening: return "listening";
    case VoiceState::kExecuting: return "executing";
  }
  return "?";
}

VoiceLoop::VoiceLoop(WakeWordDetector& wake_word, SpeechRecognizer& recognizer,
                     SpeechSynthesizer& synthesizer, Responder responder, AudioSink sink,
                     const VoiceLoopOptions& options)
    : wake_word_(wake_word),
      recognizer_(recognizer),
      synthesizer_(synthesizer),
      responder_(std::move(responder)),
      sink_(std::move(sink)),
      endpointer_(options.endpointer) {
  detections_.reserve(4);
  wake_word_.reset();
}

void VoiceLoop::set_state(VoiceState state) {
  if (state == state_) return;
  state_ = state;
  if (state_listener_) state_listener_(state);
}

void VoiceLoop::start_listening(std::int64_t wake_sample) {
  turn_ = VoiceTurn{};
  turn_.wake_sample = wake_sample;
  listen_start_ = samples_;
  endpointer_.reset();
  recognizer_.begin();
  set_state(VoiceState::kListening);
}

void VoiceLoop::feed(std::span<const std::int16_t> samples) {
  while (!samples.empty()) {
    if (state_ == VoiceState::kAwaiting) {
      detections_.clear();
      // Through the detector in 10 ms steps, so the command after the keyword is split off
      // where the keyword ended.
      const std::size_t n = std::min<std::size_t>(160, samples.size());
      wake_word_.process(samples.first(n), detections_);
      samples_ += static_cast<std::int64_t>(n);
      samples = samples.subspan(n);
      if (!detections_.empty()) {
        start_listening(wake_word_base_ + detections_.back().end_sample);
      }
      continue;
    }
    // Listening: the endpointer decides how much of this chunk belongs to the command.
    const std::int64_t before = endpointer_.samples_seen();
    const EndpointState state = endpointer_.push(samples);
    const auto used = static_cast<std::size_t>(endpointer_.samples_seen() - before);
    recognizer_.feed(samples.first(used));
    samples_ += static_cast<std::int64_t>(used);
    samples = samples.subspan(used);
    if (state == EndpointState::kEnded || state == EndpointState::kTimedOut) {
      complete_turn(state == EndpointState::kTimedOut, std::chrono::steady_clock::now());
    }
  }
}

void VoiceLoop::finish() {
  if (state_ == VoiceState::kListening) {
    complete_turn(endpointer_.state() == EndpointState::kWaitingForSpeech,
                  std::chrono::steady_clock::now());
  }
}

void VoiceLoop::complete_turn(bool timed_out, std::chrono::steady_clock::time_point decided) {
  turn_.timed_out = timed_out;
  turn_.speech_begin_sample = listen_start_ + endpointer_.speech_begin();
  turn_.speech_end_sample = listen_start_ + endpointer_.speech_end();
  turn_.endpoint_sample = samples_;
  turn_.recognition = recognizer_.end();
  set_state(VoiceState::kExecuting);
  if (!timed_out) {
    turn_.reply = responder_(turn_.recognition);
    bool first = true;
    if (!turn_.reply.text.empty()) {
      const bool complete = synthesizer_.speak(turn_.reply.text, [&](std::span<const std::int16_t> chunk) {
        if (first) {
          turn_.compute_to_first_audio = std::chrono::steady_clock::now() - decided;
          first = false;
        }
        sink_(chunk);
      });
      turn_.reply_interrupted = !complete;
    }
  }
  if (turn_listener_) turn_listener_(turn_);
  if (!command_grammar_.empty()) {
    recognizer_.set_grammar(command_grammar_);
    command_grammar_.clear();
  }
  if (!timed_out && turn_.reply.expects_answer) {
    if (!turn_.reply.answer_grammar.empty()) {
      command_grammar_ = recognizer_.grammar();
      recognizer_.set_grammar(turn_.reply.answer_grammar);
    }
    start_listening(-1);
    return;
  }
  wake_word_.reset();
  wake_word_base_ = samples_;
  set_state(VoiceState::kAwaiting);
}

}  // namespace marvin::perception
