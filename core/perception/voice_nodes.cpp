#include "perception/voice_nodes.h"

#include <algorithm>
#include <chrono>
#include <fstream>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>

#include "devices/audio/sound_file.h"
#include "graph/attention_node.h"
#include "graph/audio_chunk.h"
#include "graph/node.h"
#include "perception/command_grammar.h"
#include "perception/endpointer.h"
#include "perception/log_mel.h"
#include "perception/pocketsphinx_wake_word.h"
#include "perception/speech_synthesizer.h"

namespace marvin::perception {
namespace {

using graph::AudioChunk;
using graph::Context;
using graph::Contract;
using graph::Node;
using graph::Timestamp;

constexpr int kRate = 16000;

Timestamp sample_time(std::int64_t sample) { return sample * 1'000'000 / kRate; }

class AudioFileSource : public Node {
 public:
  static void declare(Contract& c) {
    c.add_output<AudioChunk>("out");
    c.option_string("path", "");
    c.option_int("chunk_ms", 20, 1, 1000);
    c.option_double("pace", 0.0, 0.0, 1000.0);
  }
  void open(Context& ctx) override {
    const std::string path = ctx.options().get_string("path");
    if (path.empty()) throw std::runtime_error("AudioFileSource: option \"path\" is required");
    samples_ = audio::read_speech_file(path);
    chunk_ = static_cast<std::size_t>(ctx.options().get_int("chunk_ms")) * kRate / 1000;
    pace_ = ctx.options().get_double("pace");
  }
  void process(Context& ctx) override {
    if (pos_ >= samples_.size() || ctx.stop_requested()) {
      ctx.finish();
      return;
    }
    const std::size_t n = std::min(chunk_, samples_.size() - pos_);
    AudioChunk chunk;
    chunk.sample_rate = kRate;
    chunk.samples.assign(samples_.begin() + static_cast<std::ptrdiff_t>(pos_),
                         samples_.begin() + static_cast<std::ptrdiff_t>(pos_ + n));
    ctx.emit(0, graph::Packet::make<AudioChunk>(std::move(chunk))
                    .at(sample_time(static_cast<std::int64_t>(pos_))));
    pos_ += n;
    if (pace_ > 0) {
      ctx.wake_after(std::chrono::nanoseconds(
          static_cast<std::int64_t>(static_cast<double>(n) * 1e9 / kRate / pace_)));
    }
  }

 private:
  std::vector<std::int16_t> samples_;
  std::size_t chunk_ = 320;
  std::size_t pos_ = 0;
  double pace_ = 0;
};

class LogMelFeatures : public Node {
 public:
  static void declare(Contract& c) {
    c.add_input<AudioChunk>("in");
    c.add_output<LogMelFrames>("out");
  }
  void process(Context& ctx) override {
    const AudioChunk& chunk = ctx.input(0).get<AudioChunk>();
    LogMelFrames frames;
    frames.first_frame = next_frame_;
    frames.num_bins = static_cast<int>(extractor_.num_bins());
    next_frame_ += static_cast<std::int64_t>(extractor_.push(chunk.samples, [&](std::span<const float> bins) {
      frames.values.insert(frames.values.end(), bins.begin(), bins.end());
    }));
    if (!frames.values.empty()) ctx.emit(0, std::move(frames));
  }

 private:
  LogMelExtractor extractor_;
  std::int64_t next_frame_ = 0;
};

class WakeWordAttention : public graph::AttentionNode {
 public:
  static void declare(Contract& c) {
    c.add_input<AudioChunk>("in");
    add_state_output(c, "listening");
    c.option_double("sensitivity", 0.5, 0.0, 1.0);
    c.option_int("trailing_silence_ms", 400, 10, 10000);
    c.option_int("no_speech_timeout_ms", 5000, 100, 60000);
  }
  void open(Context& ctx) override {
    PocketsphinxWakeWordOptions options;
    options.sensitivity = static_cast<float>(ctx.options().get_double("sensitivity"));
    detector_ = std::make_unique<PocketsphinxWakeWord>(options);
    EndpointerOptions endpoint;
    endpoint.trailing_silence_ms = static_cast<int>(ctx.options().get_int("trailing_silence_ms"));
    endpoint.no_speech_timeout_ms = static_cast<int>(ctx.options().get_int("no_speech_timeout_ms"));
    endpointer_ = std::make_unique<Endpointer>(endpoint);
  }
  void process(Context& ctx) override {
    const AudioChunk& chunk = ctx.input(0).get<AudioChunk>();
    const Timestamp start = ctx.input_timestamp();
    std::span<const std::int16_t> rest(chunk.samples);
    bool changed = false;
    while (!rest.empty()) {
      if (!listening_) {
        detections_.clear();
        const std::int64_t base = fed_;
        detector_->process(rest, detections_);
        fed_ += static_cast<std::int64_t>(rest.size());
        if (detections_.empty()) break;
        // Listening from the end of the keyword; the rest of the chunk is already past the
        // detector, so the endpointer starts with the next chunk.
        const std::int64_t offset = detections_.back().end_sample - base;
        set_state(ctx, 0, true, start + sample_time(std::max<std::int64_t>(offset, 0)));
        listening_ = true;
        changed = true;
        endpointer_->reset();
        break;
      }
      const std::int64_t before = endpointer_->samples_seen();
      const EndpointState state = endpointer_->push(rest);
      const auto used = static_cast<std::size_t>(endpointer_->samples_seen() - before);
      if (state == EndpointState::kEnded || state == EndpointState::kTimedOut) {
        set_state(ctx, 0, false, start + sample_time(static_cast<std::int64_t>(used)));
        listening_ = false;
        changed = true;
        detector_->reset();
        fed_ = 0;
      }
      break;
    }
    if (!changed) set_state(ctx, 0, listening_);
  }

 private:
  std::unique_ptr<PocketsphinxWakeWord> detector_;
  std::unique_ptr<Endpointer> endpointer_;
  std::vector<WakeWordDetection> detections_;
  std::int64_t fed_ = 0;
  bool listening_ = false;
};

std::vector<GrammarIntent> demo_intents() {
  return {
      {"time", {"what time is it", "what's the time", "tell me the time"}, {}},
      {"call", {"(call|phone|ring) {contact}"}, {{"contact", SlotKind::kPhrases, {"anna", "bob"}}}},
      {"lights", {"(turn|switch) (on|off) [the] {device}"},
       {{"device", SlotKind::kPhrases, {"lamp", "fan", "radio", "kitchen light"}}}},
      {"timer", {"set [a] timer for {duration}"}, {{"duration", SlotKind::kDuration, {}}}},
  };
}

class SpeechRecognizerNode : public Node {
 public:
  static void declare(Contract& c) {
    c.add_input<AudioChunk>("audio");
    c.add_input<bool>("listening");
    c.add_output<Recognition>("utterance");
    c.option_string("grammar_file", "");
    c.option_double("rejection_threshold", -3.0);
  }
  void open(Context& ctx) override {
    RecognizerOptions options;
    options.rejection_threshold = static_cast<float>(ctx.options().get_double("rejection_threshold"));
    recognizer_ = std::make_unique<SpeechRecognizer>(options);
    const std::string file = ctx.options().get_string("grammar_file");
    if (file.empty()) {
      const std::vector<GrammarIntent> intents = demo_intents();
      recognizer_->set_grammar(build_command_grammar(intents, {}, [this](std::string_view w) {
                                 return recognizer_->knows_word(w);
                               }).jsgf);
    } else {
      std::ifstream in(file);
      if (!in) throw std::runtime_error("SpeechRecognizerNode: cannot read grammar_file " + file);
      std::ostringstream text;
      text << in.rdbuf();
      recognizer_->set_grammar(text.str());
    }
  }
  void process(Context& ctx) override {
    if (ctx.has_input(0) && recognizer_->in_utterance()) {
      recognizer_->feed(ctx.input(0).get<AudioChunk>().samples);
    }
    if (ctx.has_input(1)) {
      if (ctx.input(1).get<bool>()) {
        recognizer_->begin();
      } else if (recognizer_->in_utterance()) {
        ctx.emit(0, recognizer_->end());
      }
    }
  }
  void close(Context& ctx) override {
    (void)ctx;
    if (recognizer_ && recognizer_->in_utterance()) recognizer_->end();
  }

 private:
  std::unique_ptr<SpeechRecognizer> recognizer_;
};

class EchoReply : public Node {
 public:
  static void declare(Contract& c) {
    c.add_input<Recognition>("in");
    c.add_output<std::string>("out");
  }
  void process(Context& ctx) override {
    const Recognition& r = ctx.input(0).get<Recognition>();
    ctx.emit(0, std::string(r.matched ? "You said: " + r.text : "Sorry, I did not understand."));
  }
};

class SpeechSynthesisNode : public Node {
 public:
  static void declare(Contract& c) {
    c.add_input<std::string>("in");
    c.add_output<AudioChunk>("out");
    c.option_string("voice", "en-us");
    c.option_int("rate", 160, 80, 450);
  }
  void open(Context& ctx) override {
    SynthesisOptions options;
    options.voice = ctx.options().get_string("voice");
    options.rate_wpm = static_cast<int>(ctx.options().get_int("rate"));
    synthesizer_ = std::make_unique<SpeechSynthesizer>(options);
  }
  void process(Context& ctx) override {
    Timestamp next = std::max(ctx.input_timestamp(), next_free_);
    std::int64_t written = 0;
    synthesizer_->speak(ctx.input(0).get<std::string>(), [&](std::span<const std::int16_t> pcm) {
      AudioChunk chunk;
      chunk.samples.assign(pcm.begin(), pcm.end());
      ctx.emit(0, graph::Packet::make<AudioChunk>(std::move(chunk)).at(next + sample_time(written)));
      written += static_cast<std::int64_t>(pcm.size());
    });
    next_free_ = next + sample_time(written) + 1;
  }

 private:
  std::unique_ptr<SpeechSynthesizer> synthesizer_;
  Timestamp next_free_ = graph::kTimestampMin;
};

class AudioFileSink : public Node {
 public:
  static void declare(Contract& c) {
    c.add_input<AudioChunk>("in");
    c.option_string("path", "");
  }
  void open(Context& ctx) override {
    path_ = ctx.options().get_string("path");
    if (path_.empty()) throw std::runtime_error("AudioFileSink: option \"path\" is required");
  }
  void process(Context& ctx) override {
    const AudioChunk& chunk = ctx.input(0).get<AudioChunk>();
    const auto at = static_cast<std::size_t>(std::max<Timestamp>(ctx.input_timestamp(), 0) * kRate / 1'000'000);
    if (samples_.size() < at) samples_.resize(at, 0);
    samples_.insert(samples_.end(), chunk.samples.begin(), chunk.samples.end());
  }
  void close(Context& ctx) override {
    (void)ctx;
    audio::write_speech_file(path_, samples_);
  }

 private:
  std::string path_;
  std::vector<std::int16_t> samples_;
};

template <typename N>
void add(graph::NodeRegistry& registry, const char* name) {
  if (registry.find(name) != nullptr) return;
  registry.add({name, &N::declare, []() -> std::unique_ptr<Node> { return std::make_unique<N>(); }});
}

}  // namespace

void register_voice_nodes(graph::NodeRegistry& registry) {
  add<AudioFileSource>(registry, "AudioFileSource");
  add<LogMelFeatures>(registry, "LogMelFeatures");
  add<WakeWordAttention>(registry, "WakeWordAttention");
  add<SpeechRecognizerNode>(registry, "SpeechRecognizerNode");
  add<EchoReply>(registry, "EchoReply");
  add<SpeechSynthesisNode>(registry, "SpeechSynthesisNode");
  add<AudioFileSink>(registry, "AudioFileSink");
}

}  // namespace marvin::perception
