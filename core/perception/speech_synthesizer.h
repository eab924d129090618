// Speech synthesis with the espeak-ng library, delivered as 16 kHz mono PCM16.
//
// espeak-ng keeps process-wide state, so every SpeechSynthesizer shares one engine behind a
// mutex: two speak() calls on different threads run one after the other. Voice, rate and
// pitch are per object and applied at each speak().
//
// interrupt() ("Marvin, stop") may be called from any thread: the speak() in progress stops
// within one engine buffer (about 20 ms of audio) and returns false.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace marvin::perception {

struct SynthesisOptions {
  std::string voice = "en-us";  // an espeak-ng voice name ("en", "en-us", "de", ...)
  int rate_wpm = 160;           // words per minute, 80..450
  int pitch = 50;               // 0..100
  int volume = 100;             // 0..200
};

class SpeechSynthesizer {
 public:
  // Starts the engine on first use. Throws std::runtime_error when espeak-ng's data is
  // missing, the voice is unknown or a setting is out of range.
  explicit SpeechSynthesizer(const SynthesisOptions& options = {});

  const SynthesisOptions& options() const { return options_; }
  void set_options(const SynthesisOptions& options);  // validated as in the constructor

  // Speaks `text`, calling `sink` with consecutive chunks of audio as they are made (the
  // first arrives long before the sentence is finished). Returns true when everything was
  // spoken, false when interrupt() cut it short. Exceptions from `sink` propagate after the
  // engine is stopped.
  bool speak(std::string_view text, const std::function<void(std::span<const std::int16_t>)>& sink);

  // The whole utterance as one buffer.
  std::vector<std::int16_t> synthesize(std::string_view text);

  // Stops the speak() in progress, if any (returns immediately).
  void interrupt() { interrupted_.store(true); }

  static constexpr int kSampleRate = 16000;

 private:
  SynthesisOptions options_;
  std::atomic<bool> interrupted_{false};
};

}  // namespace marvin::perception
