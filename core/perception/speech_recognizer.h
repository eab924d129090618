// Speech recognition of one command at a time, constrained by the command grammar.
//
// Two pocketsphinx decoders listen to the same audio: one searches the JSGF grammar
// (command_grammar.h), the other a free loop of the model's 39 phones. At the end, the grammar path's score
// minus the phone loop's, per 10 ms frame, says how well the best sentence explains the
// sound compared to any sequence of phones: in-grammar speech scores near or above zero,
// speech the grammar cannot express below (measured on espeak-ng speech with the test
// grammar: correct commands -2.2..+10.6; out-of-grammar sentences and gibberish -4.3..-18,
// or no path through the grammar at all). Below `rejection_threshold` the result is "no
// match", not a forced wrong sentence. The margin is thin for short commands; tune the
// threshold on recordings from the robot's own microphone.
//
// The scale depends on the grammar's size, measured with the host's grammar (two built-in
// skills, ~30 templates, dates, numbers, contact and task phrases): pocketsphinx scores each
// frame against the best senone among those its search keeps active, so a larger grammar
// makes the same sentence score lower ("tell me the time": +7.9 alone, -23 in the host's
// grammar), and with the default beams its path is pruned in favour of a worse one that
// fits the start better. For large grammars pass {"-compallsen", "yes"} (every senone, every
// frame: a scale independent of the grammar, ~30% more CPU) and wider beams, and set the
// threshold on that scale: the host's voice front end uses kLargeGrammarSettings and
// kLargeGrammarThreshold below (espeak-ng speech: in-grammar -22..-7, out of grammar -32..-27
// or no path, one near miss at -19).
//
// Usage per utterance: begin(), feed() as audio arrives, end() for the result. Not
// thread-safe; one utterance at a time. set_grammar() between utterances.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "perception/sphinx_model.h"

namespace marvin::perception {

struct RecognizerOptions {
  SphinxModel model;
  float rejection_threshold = -3.0f;  // minimum (grammar - phone loop) score per frame
  // Extra pocketsphinx settings for both decoders, e.g. {"-maxhmmpf", "3000"} (see
  // speech_recognizer.cpp for the defaults chosen).
  std::vector<std::pair<std::string, std::string>> decoder_settings;
};

struct Recognition {
  bool matched = false;
  std::string text;         // the sentence (lower case, words separated by one space)
  float confidence = 0.0f;  // (grammar - phone loop) score per frame; see above
  std::string reason;       // when !matched: why ("no sentence of the grammar fits", ...)
  std::int64_t samples = 0; // audio length of the utterance
};

// Settings for grammars of many templates (see above).
inline const std::vector<std::pair<std::string, std::string>> kLargeGrammarSettings = {
    {"-compallsen", "yes"}, {"-beam", "1e-80"}, {"-pbeam", "1e-80"}, {"-wbeam", "1e-60"}};
inline constexpr float kLargeGrammarThreshold = -24.0f;

class SpeechRecognizer {
 public:
  // Loads the model twice (~0.25 s). Throws std::runtime_error when it is missing.
  explicit SpeechRecognizer(const RecognizerOptions& options = {});
  ~SpeechRecognizer();
  SpeechRecognizer(const SpeechRecognizer&) = delete;
  SpeechRecognizer& operator=(const SpeechRecognizer&) = delete;

  // Replaces the grammar (JSGF text). Throws std::runtime_error when pocketsphinx refuses
  // it; the previous grammar then stays. Must not be called inside an utterance. Setting
  // the same text again costs nothing.
  void set_grammar(const std::string& jsgf);
  bool has_grammar() const;
  const std::string& grammar() const;  // the JSGF text in use ("" before set_grammar)

  // Whether the dictionary has a pronunciation for `word` (pass to build_command_grammar).
  bool knows_word(std::string_view word) const;

  void begin();
  // 16 kHz mono PCM16.
  void feed(std::span<const std::int16_t> samples);
  Recognition end();

  // begin(), feed(samples), end().
  Recognition recognize(std::span<const std::int16_t> samples);

  bool in_utterance() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace marvin::perception
