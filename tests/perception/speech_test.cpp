// End to end on speech made by espeak-ng during the test: no recorded audio, no mocks.
#include <doctest/doctest.h>

#include <string>
#include <vector>

#include "perception/voice_loop.h"
#include "speech_fixture.h"

using namespace marvin::perception;
using namespace marvin::perception::testing;

namespace {

// Runs a VoiceLoop over `audio` and records what it did.
struct LoopRun {
  std::vector<VoiceState> states;
  std::vector<VoiceTurn> turns;
  std::vector<std::int16_t> reply_audio;
  std::vector<std::string> heard;  // recognitions handed to the responder ("" = no match)

  explicit LoopRun(const std::vector<std::int16_t>& audio,
                   std::function<Reply(const Recognition&)> respond = {}) {
    if (!respond) {
      respond = [](const Recognition& r) {
        return Reply{r.matched ? "It is ten past eight." : "Sorry, I did not understand.", false, {}};
      };
    }
    VoiceLoop loop(
        wake_word(), recognizer(), synthesizer(),
        [&](const Recognition& r) {
          heard.push_back(r.matched ? r.text : "");
          return respond(r);
        },
        [&](std::span<const std::int16_t> chunk) {
          reply_audio.insert(reply_audio.end(), chunk.begin(), chunk.end());
        });
    states.push_back(loop.state());
    loop.on_state([&](VoiceState s) { states.push_back(s); });
    loop.on_turn([&](const VoiceTurn& t) { turns.push_back(t); });
    for (std::size_t pos = 0; pos < audio.size(); pos += 512) {
      loop.feed(std::span<const std::int16_t>(audio).subspan(pos, std::min<std::size_t>(512, audio.size() - pos)));
    }
    loop.finish();
  }
};

}  // namespace

TEST_CASE("synthesised speech is speech: long enough, loud enough, interruptible") {
  const std::vector<std::int16_t> pcm = synthesizer().synthesize("It is ten past eight.");
  CHECK(pcm.size() > 16000 / 2);   // over half a second
  CHECK(pcm.size() < 16000 * 5);
  CHECK(rms(pcm) > 1000.0);        // about -30 dBFS and up

  // interrupt() from the sink, after the first chunk: the rest is not made.
  std::size_t delivered = 0;
  const bool complete = synthesizer().speak("This is a long answer that the user stops early.",
                                            [&](std::span<const std::int16_t> chunk) {
                                              delivered += chunk.size();
                                              synthesizer().interrupt();
                                            });
  CHECK_FALSE(complete);
  CHECK(delivered > 0);
  CHECK(delivered < pcm.size());
  // The next sentence is spoken in full again.
  CHECK(synthesizer().synthesize("Yes.").size() > 1000);
}

TEST_CASE("synthesis settings are validated") {
  SynthesisOptions options;
  options.voice = "no-such-voice";
  CHECK_THROWS_WITH(SpeechSynthesizer{options}, doctest::Contains("no-such-voice"));
  options = {};
  options.rate_wpm = 20;
  CHECK_THROWS_WITH(SpeechSynthesizer{options}, doctest::Contains("rate_wpm"));
  options = {};
  options.rate_wpm = 220;  // faster speech is shorter
  SpeechSynthesizer fast(options);
  CHECK(fast.synthesize("what time is it").size() < synthesizer().synthesize("what time is it").size());
}

TEST_CASE("the wake word fires on \"marvin\" and not on a command without it") {
  PocketsphinxWakeWord& detector = wake_word();
  std::vector<WakeWordDetection> detections;

  detector.reset();
  const std::vector<std::int16_t> with = utterance("marvin, what time is it");
  detector.process(with, detections);
  REQUIRE(detections.size() == 1);
  // "marvin" is spoken after 500 ms of silence and lasts about half a second.
  CHECK(detections[0].end_sample > 500 * 16);
  CHECK(detections[0].end_sample < 1600 * 16);
  CHECK(detections[0].begin_sample < detections[0].end_sample);

  detections.clear();
  detector.reset();
  detector.process(utterance("what time is it"), detections);
  detector.process(utterance("turn on the lamp"), detections);
  CHECK(detections.empty());
}

TEST_CASE("sensitivity changes what the wake word accepts") {
  PocketsphinxWakeWord detector([] {
    PocketsphinxWakeWordOptions o;
    o.sensitivity = 0.0f;  // strictest
    return o;
  }());
  const std::vector<std::int16_t> audio = utterance("marvin, what time is it");
  std::vector<WakeWordDetection> detections;
  detector.process(audio, detections);
  CHECK(detections.empty());
  detector.set_sensitivity(0.5f);
  CHECK(detector.sensitivity() == 0.5f);
  detector.reset();
  detector.process(audio, detections);
  CHECK(detections.size() == 1);
  CHECK(PocketsphinxWakeWord::threshold_for(0.0f) > PocketsphinxWakeWord::threshold_for(1.0f));
}

TEST_CASE("the recognizer yields in-grammar sentences and rejects the rest") {
  SpeechRecognizer& r = recognizer();
  for (const char* sentence : {"what time is it", "call anna", "turn on the lamp",
                               "switch off the kitchen light"}) {
    CAPTURE(sentence);
    const Recognition result = r.recognize(utterance(sentence, 300, 500));
    CAPTURE(result.reason);
    CHECK(result.matched);
    CHECK(result.text == sentence);
  }
  for (const char* sentence : {"blorf znak quibble tarradiddle", "the weather in paris is nice",
                               "please open the window"}) {
    CAPTURE(sentence);
    const Recognition result = r.recognize(utterance(sentence, 300, 500));
    CAPTURE(result.text);
    CHECK_FALSE(result.matched);
    CHECK(result.text.empty());
    CHECK_FALSE(result.reason.empty());
  }
}

TEST_CASE("regenerating the grammar lets new contacts be recognised") {
  SpeechRecognizer r;
  auto known = [&r](std::string_view w) { return r.knows_word(w); };
  const std::vector<std::int16_t> audio = utterance("call peter", 300, 500);
  r.set_grammar(build_command_grammar(test_intents({"anna", "bob"}), {}, known).jsgf);
  const Recognition before = r.recognize(audio);
  CHECK(before.text != "call peter");
  r.set_grammar(build_command_grammar(test_intents({"anna", "bob", "peter"}), {}, known).jsgf);
  const Recognition after = r.recognize(audio);
  CHECK(after.matched);
  CHECK(after.text == "call peter");
  CHECK_THROWS_WITH(r.set_grammar("#JSGF V1.0;\ngrammar g;\npublic <s> = (unclosed;\n"),
                    doctest::Contains("refused"));
  CHECK(r.recognize(audio).text == "call peter");  // the previous grammar stays
}

TEST_CASE("voice loop: \"marvin, what time is it\" is heard, answered, and the light follows") {
  const LoopRun run(utterance("marvin, what time is it"));
  REQUIRE(run.turns.size() == 1);
  CHECK(run.heard == std::vector<std::string>{"what time is it"});
  CHECK(run.turns[0].recognition.matched);
  CHECK(run.turns[0].speech_end_sample > run.turns[0].wake_sample);
  CHECK(run.states == std::vector<VoiceState>{VoiceState::kAwaiting, VoiceState::kListening,
                                              VoiceState::kExecuting, VoiceState::kAwaiting});
  CHECK(run.reply_audio.size() > 16000 / 2);
  CHECK(rms(run.reply_audio) > 1000.0);
}

TEST_CASE("voice loop: a command without the wake word is ignored") {
  std::vector<std::int16_t> audio = utterance("what time is it");
  const std::vector<std::int16_t> more = utterance("call anna");
  audio.insert(audio.end(), more.begin(), more.end());
  const LoopRun run(audio);
  CHECK(run.turns.empty());
  CHECK(run.heard.empty());
  CHECK(run.reply_audio.empty());
  CHECK(run.states == std::vector<VoiceState>{VoiceState::kAwaiting});
}

TEST_CASE("voice loop: gibberish after \"marvin\" gets the no-match answer") {
  const LoopRun run(utterance("marvin, blorf znak quibble tarradiddle"));
  REQUIRE(run.turns.size() == 1);
  CHECK(run.heard == std::vector<std::string>{""});
  CHECK_FALSE(run.turns[0].recognition.matched);
  CHECK(run.turns[0].reply.text == "Sorry, I did not understand.");
  CHECK(rms(run.reply_audio) > 1000.0);
}

TEST_CASE("voice loop: a question is answered without the wake word, then it waits again") {
  // The answer comes after the question has been spoken (about 1.2 s from the endpoint).
  std::vector<std::int16_t> audio = utterance("marvin, call", 500, 2500);
  for (const char* next : {"anna", "what time is it"}) {
    const std::vector<std::int16_t> more = utterance(next);
    audio.insert(audio.end(), more.begin(), more.end());
  }
  const std::vector<GrammarIntent> answer = {
      {"answer", {"[call] {contact}"}, {{"contact", SlotKind::kPhrases, {"anna", "bob"}}}}};
  const std::string answer_grammar = build_command_grammar(answer).jsgf;
  const std::string command_grammar = recognizer().grammar();
  const LoopRun run(audio, [&](const Recognition& r) {
    if (!r.matched) return Reply{"Whom should I call?", true, answer_grammar};
    return Reply{"Calling " + r.text + ".", false, {}};
  });
  CHECK(recognizer().grammar() == command_grammar);  // restored after the answer
  // "call" alone is not a sentence of the grammar -> question; "anna" answers it; the last
  // command has no wake word and is ignored.
  REQUIRE(run.turns.size() == 2);
  CHECK(run.heard == std::vector<std::string>{"", "anna"});
  CHECK(run.turns[1].wake_sample == -1);
  CHECK(run.states == std::vector<VoiceState>{VoiceState::kAwaiting, VoiceState::kListening,
                                              VoiceState::kExecuting, VoiceState::kListening,
                                              VoiceState::kExecuting, VoiceState::kAwaiting});
}

namespace {

// The pocketsphinx spotter reporting each keyword `delay` samples after it ended, with the
// same end_sample: a detector that becomes sure late, as the embedding wake word does at a
// low sensitivity.
class LateWakeWord : public WakeWordDetector {
 public:
  explicit LateWakeWord(std::int64_t delay) : delay_(delay) {}
  const std::string& keyword() const override { return inner_.keyword(); }
  void set_sensitivity(float s) override { inner_.set_sensitivity(s); }
  float sensitivity() const override { return inner_.sensitivity(); }
  std::size_t process(std::span<const std::int16_t> samples,
                      std::vector<WakeWordDetection>& detections) override {
    inner_.process(samples, held_);
    seen_ += static_cast<std::int64_t>(samples.size());
    std::size_t added = 0;
    while (!held_.empty() && seen_ >= held_.front().end_sample + delay_) {
      detections.push_back(held_.front());
      held_.erase(held_.begin());
      ++added;
    }
    return added;
  }
  void reset() override {
    inner_.reset();
    held_.clear();
    seen_ = 0;
  }

 private:
  PocketsphinxWakeWord inner_;
  std::int64_t delay_;
  std::int64_t seen_ = 0;
  std::vector<WakeWordDetection> held_;
};

}  // namespace

TEST_CASE("voice loop: a detector sure of the wake word 0.4 s late still hears the whole command") {
  // "marvin, what time is it": the command starts at the detection's end_sample, 0.4 s before
  // the detection; without going back there the recognizer would get "...time is it".
  const std::vector<std::int16_t> audio = utterance("marvin, what time is it", 500, 3000);
  LateWakeWord late(6400);
  std::vector<std::string> heard;
  std::vector<VoiceTurn> turns;
  std::vector<std::int16_t> out;
  VoiceLoopOptions options;
  options.aligned_output = true;
  VoiceLoop loop(
      late, recognizer(), synthesizer(),
      [&](const Recognition& r) {
        heard.push_back(r.matched ? r.text : "");
        return Reply{"It is ten past eight.", false, {}};
      },
      [&](std::span<const std::int16_t> chunk) {
        out.insert(out.end(), chunk.begin(), chunk.end());
      },
      options);
  loop.on_turn([&](const VoiceTurn& t) { turns.push_back(t); });
  for (std::size_t pos = 0; pos < audio.size(); pos += 512) {
    loop.feed(std::span<const std::int16_t>(audio).subspan(
        pos, std::min<std::size_t>(512, audio.size() - pos)));
  }
  loop.finish();
  REQUIRE(turns.size() == 1);
  CHECK(heard == std::vector<std::string>{"what time is it"});
  // The turn's times are the stream's: the command began after the wake word, and less than
  // the 0.4 s of delay after it.
  CHECK(turns[0].speech_begin_sample >= turns[0].wake_sample);
  CHECK(turns[0].speech_begin_sample < turns[0].wake_sample + 6400);
  // The audio heard again is not counted again: the output still lines up with the input
  // (the 3 s after the command hold the whole reply).
  CHECK(out.size() == audio.size());
}

TEST_CASE("voice loop: silence after the wake word times out quietly") {
  std::vector<std::int16_t> audio = utterance("marvin", 500, 0);
  audio.resize(audio.size() + 6 * 16000, 0);
  const LoopRun run(audio);
  REQUIRE(run.turns.size() == 1);
  CHECK(run.turns[0].timed_out);
  CHECK(run.heard.empty());
  CHECK(run.reply_audio.empty());
  CHECK(run.states.back() == VoiceState::kAwaiting);
}

namespace {

// Index of the first sample louder than the hiss, from `from` on (or size()).
std::size_t first_loud(const std::vector<std::int16_t>& pcm, std::size_t from = 0) {
  for (std::size_t i = from; i < pcm.size(); ++i) {
    if (std::abs(pcm[i]) > 300) return i;
  }
  return pcm.size();
}

}  // namespace

TEST_CASE("voice loop timeline: the reply starts at the endpoint, aligned with the input") {
  const std::vector<std::int16_t> audio = utterance("marvin, what time is it", 500, 3000);
  std::vector<std::int16_t> out;
  std::vector<VoiceTurn> turns;
  VoiceLoopOptions options;
  options.aligned_output = true;
  VoiceLoop loop(
      wake_word(), recognizer(), synthesizer(),
      [](const Recognition&) { return Reply{"It is ten past eight.", false, {}}; },
      [&](std::span<const std::int16_t> chunk) { out.insert(out.end(), chunk.begin(), chunk.end()); },
      options);
  loop.on_turn([&](const VoiceTurn& t) { turns.push_back(t); });
  for (std::size_t pos = 0; pos < audio.size(); pos += 320) {
    loop.feed(std::span<const std::int16_t>(audio).subspan(pos, std::min<std::size_t>(320, audio.size() - pos)));
  }
  loop.finish();
  REQUIRE(turns.size() == 1);
  // The 3 s after the command hold the whole reply: nothing is left for finish().
  CHECK(out.size() == audio.size());
  const std::size_t reply_at = first_loud(out);
  CHECK(static_cast<std::int64_t>(reply_at) >= turns[0].endpoint_sample);
  CHECK(static_cast<std::int64_t>(reply_at) < turns[0].endpoint_sample + 1600);  // espeak's lead-in
  CHECK(turns[0].reply_samples > 16000 / 2);
  // The endpoint comes after the trailing silence, which follows the end of speech.
  CHECK(turns[0].endpoint_sample - turns[0].speech_end_sample >=
        options.endpointer.trailing_silence_ms * 16 - 160);
}

TEST_CASE("voice loop barge-in: the wake word cuts the reply; say() and expect_answer() queue") {
  // A long reply; "marvin, stop" one second into it.
  std::vector<std::int16_t> audio = utterance("marvin, what time is it", 500, 1000);
  const std::size_t stop_at = audio.size();
  const std::vector<std::int16_t> stop = utterance("marvin, stop", 0, 3000);
  audio.insert(audio.end(), stop.begin(), stop.end());
  const std::string long_reply =
      "It is ten past eight in the evening, and the weather tomorrow will be sunny with a light "
      "breeze from the west.";
  std::vector<std::int16_t> out;
  std::vector<std::int64_t> cuts;
  std::vector<std::string> heard;
  std::vector<VoiceState> states;
  VoiceLoopOptions options;
  options.aligned_output = true;
  VoiceLoop loop(
      wake_word(), recognizer(), synthesizer(),
      [&](const Recognition& r) {
        heard.push_back(r.matched ? r.text : "");
        return Reply{heard.size() == 1 ? long_reply : "", false, {}};
      },
      [&](std::span<const std::int16_t> chunk) { out.insert(out.end(), chunk.begin(), chunk.end()); },
      options);
  loop.on_barge_in([&](std::int64_t at) { cuts.push_back(at); });
  loop.on_state([&](VoiceState s) { states.push_back(s); });
  for (std::size_t pos = 0; pos < audio.size(); pos += 320) {
    loop.feed(std::span<const std::int16_t>(audio).subspan(pos, std::min<std::size_t>(320, audio.size() - pos)));
  }
  REQUIRE(heard.size() == 2);
  CHECK(heard[1] == "stop");
  REQUIRE(cuts.size() == 1);
  CHECK(static_cast<std::size_t>(cuts[0]) > stop_at);
  CHECK(static_cast<std::size_t>(cuts[0]) < stop_at + 16000);
  CHECK(rms(std::vector<std::int16_t>(out.begin() + static_cast<std::ptrdiff_t>(stop_at) - 8000,
                                      out.begin() + static_cast<std::ptrdiff_t>(stop_at))) > 1000.0);
  // Nothing after the cut: the rest of the long reply is dropped.
  CHECK(first_loud(out, static_cast<std::size_t>(cuts[0])) == out.size());
  CHECK(states == std::vector<VoiceState>{VoiceState::kListening, VoiceState::kExecuting,
                                          VoiceState::kListening, VoiceState::kExecuting,
                                          VoiceState::kAwaiting});

  // Speech queued from outside plays at once when idle; a question queued with it is
  // listened for after it, without the wake word.
  states.clear();
  loop.say("Reminder: take your pills.");
  CHECK(loop.state() == VoiceState::kExecuting);
  loop.expect_answer("");
  const std::vector<std::int16_t> quiet(16000 * 3, 0);
  const std::size_t before = out.size();
  loop.feed(quiet);
  CHECK(first_loud(out, before) < before + 1600);
  CHECK(states == std::vector<VoiceState>{VoiceState::kExecuting, VoiceState::kListening});
  loop.finish();
}
