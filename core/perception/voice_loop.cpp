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
      options_(options),
      endpointer_(options.endpointer),
      command_grammar_(recognizer.grammar()),
      silence_(1600, 0) {
  detections_.reserve(4);
  wake_word_.reset();
}

void VoiceLoop::set_state(VoiceState state) {
  if (state == state_) return;
  state_ = state;
  if (state_listener_) state_listener_(state);
}

void VoiceLoop::reset_wake_word() {
  wake_word_.reset();
  wake_word_base_ = samples_;
}

void VoiceLoop::remember(std::span<const std::int16_t> heard) {
  recent_.insert(recent_.end(), heard.begin(), heard.end());
  if (recent_.size() > 2 * kMaxPreRollSamples) {
    recent_.erase(recent_.begin(), recent_.end() - static_cast<std::ptrdiff_t>(kMaxPreRollSamples));
  }
}

void VoiceLoop::start_listening(std::int64_t wake_sample, std::span<const std::int16_t> pre_roll) {
  turn_ = VoiceTurn{};
  turn_.wake_sample = wake_sample;
  listen_start_ = samples_ - static_cast<std::int64_t>(pre_roll.size());
  recent_.clear();
  endpointer_.reset();
  // Setting the grammar in use again costs nothing.
  if (wake_sample < 0 && !answer_grammar_.empty()) {
    recognizer_.set_grammar(answer_grammar_);
  } else {
    recognizer_.set_grammar(command_grammar_);
  }
  answer_grammar_.clear();
  answer_expected_ = false;
  recognizer_.begin();
  set_state(VoiceState::kListening);
  if (pre_roll.empty()) return;
  // Already heard, so neither emitted again nor counted in samples_. Half a second cannot
  // hold a command and the silence after it, but end the turn if it did.
  const std::int64_t before = endpointer_.samples_seen();
  const EndpointState state = endpointer_.push(pre_roll);
  recognizer_.feed(pre_roll.first(static_cast<std::size_t>(endpointer_.samples_seen() - before)));
  if (state == EndpointState::kEnded || state == EndpointState::kTimedOut) {
    complete_turn(state == EndpointState::kTimedOut, std::chrono::steady_clock::now());
  }
}

void VoiceLoop::emit(std::size_t n) {
  std::size_t played = 0;
  if (state_ != VoiceState::kListening && speaking()) {
    played = std::min(n, playback_.size() - played_);
    if (sink_) sink_(std::span<const std::int16_t>(playback_).subspan(played_, played));
    played_ += played;
  }
  if (!options_.aligned_output || !sink_) return;
  for (std::size_t rest = n - played; rest > 0;) {
    const std::size_t m = std::min(rest, silence_.size());
    sink_(std::span<const std::int16_t>(silence_).first(m));
    rest -= m;
  }
}

void VoiceLoop::feed(std::span<const std::int16_t> samples) {
  while (!samples.empty()) {
    if (state_ == VoiceState::kListening) {
      // The endpointer decides how much of this chunk belongs to the command.
      const std::int64_t before = endpointer_.samples_seen();
      const EndpointState state = endpointer_.push(samples);
      const auto used = static_cast<std::size_t>(endpointer_.samples_seen() - before);
      recognizer_.feed(samples.first(used));
      emit(used);
      samples_ += static_cast<std::int64_t>(used);
      samples = samples.subspan(used);
      if (state == EndpointState::kEnded || state == EndpointState::kTimedOut) {
        complete_turn(state == EndpointState::kTimedOut, std::chrono::steady_clock::now());
      }
      continue;
    }
    // Awaiting or speaking: through the detector in 10 ms steps, so the command after the
    // keyword is split off where the keyword ended; a step never runs past the end of the
    // speech, so listening for an answer starts exactly where the question ended.
    const bool was_speaking = speaking();
    std::size_t n = std::min<std::size_t>(160, samples.size());
    if (was_speaking) n = std::min(n, playback_.size() - played_);
    emit(n);
    detections_.clear();
    wake_word_.process(samples.first(n), detections_);
    remember(samples.first(n));
    samples_ += static_cast<std::int64_t>(n);
    samples = samples.subspan(n);
    if (!detections_.empty()) {
      if (speaking()) {  // barge-in: stop talking, listen
        playback_.clear();
        played_ = 0;
        if (barge_in_listener_) barge_in_listener_(samples_);
      }
      answer_expected_ = false;
      answer_grammar_.clear();
      // The command began where the keyword ended, perhaps some steps ago.
      const std::int64_t wake_end = wake_word_base_ + detections_.back().end_sample;
      const auto back = static_cast<std::size_t>(std::clamp<std::int64_t>(
          samples_ - wake_end, 0,
          static_cast<std::int64_t>(std::min(recent_.size(), kMaxPreRollSamples))));
      const std::vector<std::int16_t> pre_roll(recent_.end() - static_cast<std::ptrdiff_t>(back),
                                               recent_.end());
      start_listening(wake_end, pre_roll);
      continue;
    }
    if (was_speaking && !speaking()) after_speech();
  }
}

void VoiceLoop::after_speech() {
  playback_.clear();
  played_ = 0;
  if (answer_expected_) {
    start_listening(-1);
  } else {
    set_state(VoiceState::kAwaiting);
  }
}

void VoiceLoop::queue_speech(const std::string& text) {
  if (text.empty()) return;
  if (!speaking()) {
    playback_.clear();
    played_ = 0;
  }
  synthesizer_.speak(text, [&](std::span<const std::int16_t> chunk) {
    playback_.insert(playback_.end(), chunk.begin(), chunk.end());
  });
}

void VoiceLoop::say(const std::string& text) {
  queue_speech(text);
  if (state_ == VoiceState::kAwaiting && speaking()) set_state(VoiceState::kExecuting);
}

void VoiceLoop::expect_answer(const std::string& answer_grammar) {
  if (state_ == VoiceState::kListening) return;
  answer_expected_ = true;
  answer_grammar_ = answer_grammar;
  if (!speaking()) after_speech();
}

void VoiceLoop::finish() {
  finishing_ = true;
  if (state_ == VoiceState::kListening) {
    complete_turn(endpointer_.state() == EndpointState::kWaitingForSpeech,
                  std::chrono::steady_clock::now());
  }
  // No more input can interrupt it: the rest of the speech plays to its end.
  if (speaking()) {
    if (sink_) sink_(std::span<const std::int16_t>(playback_).subspan(played_));
    playback_.clear();
    played_ = 0;
  }
  if (state_ == VoiceState::kExecuting) set_state(VoiceState::kAwaiting);
  finishing_ = false;
}

void VoiceLoop::complete_turn(bool timed_out, std::chrono::steady_clock::time_point decided) {
  turn_.timed_out = timed_out;
  turn_.speech_begin_sample = listen_start_ + endpointer_.speech_begin();
  turn_.speech_end_sample = listen_start_ + endpointer_.speech_end();
  turn_.endpoint_sample = samples_;
  turn_.recognition = recognizer_.end();
  // Back to the command grammar at once (costs nothing when it is in use already).
  recognizer_.set_grammar(command_grammar_);
  set_state(VoiceState::kExecuting);
  const bool answering = turn_.wake_sample < 0;
  // Silence after the wake word needs no answer; silence after a question does (ask again
  // or give up), except at the end of the input.
  if (!timed_out || (answering && !finishing_)) {
    if (timed_out) {
      turn_.recognition = Recognition{};
      turn_.recognition.reason = "nothing said";
    }
    turn_.reply = responder_(turn_.recognition);
    const std::size_t queued = playback_.size();
    queue_speech(turn_.reply.text);
    turn_.reply_samples = static_cast<std::int64_t>(playback_.size() - queued);
    turn_.compute_to_first_audio = std::chrono::steady_clock::now() - decided;
  }
  if (turn_listener_) turn_listener_(turn_);
  reset_wake_word();
  answer_expected_ = turn_.reply.expects_answer;
  answer_grammar_ = turn_.reply.answer_grammar;
  if (!speaking()) after_speech();
}

}  // namespace marvin::perception
