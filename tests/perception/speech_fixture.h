// Shared speech parts for the voice tests: one synthesizer, wake-word detector and
// recognizer per test program (loading the pocketsphinx model takes ~0.1 s per decoder),
// and synthetic utterances made by espeak-ng at run time.
#pragma once

#include <algorithm>
#include <cmath>
#include <random>
#include <cstdint>
#include <string>
#include <vector>

#include "perception/command_grammar.h"
#include "perception/pocketsphinx_wake_word.h"
#include "perception/speech_recognizer.h"
#include "perception/speech_synthesizer.h"

namespace marvin::perception::testing {

inline SpeechSynthesizer& synthesizer() {
  static SpeechSynthesizer synth;
  return synth;
}

// `text` spoken by espeak-ng, with silence before and after, and a faint room hiss (about
// -60 dBFS, fixed seed) over everything: no microphone delivers digital zeros, and
// pocketsphinx's cepstral mean normalisation misjudges them.
inline std::vector<std::int16_t> utterance(const std::string& text, int silence_before_ms = 500,
                                           int silence_after_ms = 1000) {
  std::vector<std::int16_t> audio(static_cast<std::size_t>(silence_before_ms) * 16, 0);
  const std::vector<std::int16_t> speech = synthesizer().synthesize(text);
  audio.insert(audio.end(), speech.begin(), speech.end());
  audio.resize(audio.size() + static_cast<std::size_t>(silence_after_ms) * 16, 0);
  std::mt19937 rng(static_cast<std::uint32_t>(text.size()));
  std::normal_distribution<double> hiss(0.0, 30.0);
  for (std::int16_t& s : audio) {
    s = static_cast<std::int16_t>(std::clamp<long>(s + std::lrint(hiss(rng)), -32768, 32767));
  }
  return audio;
}

inline double rms(const std::vector<std::int16_t>& pcm) {
  double sum = 0;
  for (std::int16_t s : pcm) sum += static_cast<double>(s) * s;
  return pcm.empty() ? 0.0 : std::sqrt(sum / static_cast<double>(pcm.size()));
}

// The skills' intents as the voice tests and the benchmark know them.
inline std::vector<GrammarIntent> test_intents(std::vector<std::string> contacts = {"anna", "bob"}) {
  return {
      {"time.query", {"what time is it", "what's the time", "tell me the time"}, {}},
      {"phone.call", {"(call|phone|ring) {contact}"},
       {{"contact", SlotKind::kPhrases, std::move(contacts)}}},
      {"lights.switch", {"(turn|switch) (on|off) [the] {device}"},
       {{"device", SlotKind::kPhrases, {"lamp", "fan", "radio", "kitchen light"}}}},
      {"reminder.add", {"remind me to {task} {when}", "remind me to {task}"},
       {{"task", SlotKind::kText, {}}, {"when", SlotKind::kDateTime, {}}}},
      {"timer.set", {"set [a] timer for {duration}"}, {{"duration", SlotKind::kDuration, {}}}},
      {"weather.query", {"what's the weather [like] [today|tomorrow]"}, {}},
  };
}

inline PocketsphinxWakeWord& wake_word() {
  static PocketsphinxWakeWord detector;
  return detector;
}

inline SpeechRecognizer& recognizer() {
  static SpeechRecognizer* instance = [] {
    auto* r = new SpeechRecognizer();
    const std::vector<GrammarIntent> intents = test_intents();
    r->set_grammar(build_command_grammar(intents, {}, [r](std::string_view w) {
                     return r->knows_word(w);
                   }).jsgf);
    return r;
  }();
  return *instance;
}

}  // namespace marvin::perception::testing
