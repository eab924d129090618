#include "app/voice_host.h"

#include <algorithm>

#include "common/log.h"
#include "perception/kws/embedding_wake_word.h"
#include "perception/kws/neural_wake_word.h"
#include "perception/pocketsphinx_wake_word.h"

namespace marvin::app {

namespace perception = marvin::perception;
using devices::Light;
using perception::VoiceState;

std::unique_ptr<perception::WakeWordDetector> make_wake_word(const std::string& kind,
                                                             float sensitivity) {
  if (kind == "pocketsphinx") {
    perception::PocketsphinxWakeWordOptions options;
    options.sensitivity = sensitivity;
    return std::make_unique<perception::PocketsphinxWakeWord>(options);
  }
  if (kind == "embedding") {
    // The pretrained speech embedding + trained head (issue 21). Its ONNX files come from
    // scripts/setup; without them the host falls back to the CNN spotter and says why.
    perception::kws::EmbeddingWakeWordOptions options;
    options.sensitivity = sensitivity;
    try {
      return std::make_unique<perception::kws::EmbeddingWakeWord>(options);
    } catch (const std::exception& e) {
      log(LogLevel::kWarning, "voice",
          std::string("embedding wake word unavailable, using the cnn spotter: ") + e.what());
      return make_wake_word("cnn", sensitivity);
    }
  }
  if (kind == "neural" || kind == "cnn") {
    perception::kws::NeuralWakeWordOptions options;
    options.sensitivity = sensitivity;
    try {
      return std::make_unique<perception::kws::NeuralWakeWord>(options);
    } catch (const std::exception& e) {
      throw std::runtime_error(std::string("neural wake word: ") + e.what() +
                               " (set MARVIN_KWS_MODEL, or use --wake-word pocketsphinx)");
    }
  }
  throw std::runtime_error("unknown wake-word detector '" + kind +
                           "': expected embedding, cnn (or neural) or pocketsphinx");
}

// The body the manager and the skills see: everything goes to the host's body, the status
// light merged with the voice state (see voice_host.h).
class VoiceHost::StatusLight : public devices::Body {
 public:
  explicit StatusLight(devices::Body& inner) : inner_(inner) {}

  void move(devices::Direction direction, std::uint8_t speed,
            std::chrono::milliseconds duration) override {
    inner_.move(direction, speed, duration);
  }
  void stop() override { inner_.stop(); }
  void tilt_head(int degrees) override { inner_.tilt_head(degrees); }
  std::vector<devices::ScanPoint> latest_scan() override { return inner_.latest_scan(); }

  // From the manager and the skills.
  void set_light(Light light) override {
    std::lock_guard lock(mutex_);
    others_ = light;
    show();
  }
  // From the voice loop.
  void voice(VoiceState state) {
    std::lock_guard lock(mutex_);
    voice_ = state;
    show();
  }

 private:
  void show() {  // mutex_ held, so the changes reach the body in the order decided
    Light light = others_;
    if (voice_ == VoiceState::kListening) {
      light = Light::kListening;
    } else if (voice_ == VoiceState::kExecuting) {
      light = Light::kExecuting;
    }
    inner_.set_light(light);
  }

  devices::Body& inner_;
  std::mutex mutex_;
  Light others_ = Light::kAwaiting;
  VoiceState voice_ = VoiceState::kAwaiting;
};

namespace {

// The host's grammar is large: see speech_recognizer.h.
perception::RecognizerOptions recognizer_options() {
  perception::RecognizerOptions options;
  options.decoder_settings = perception::kLargeGrammarSettings;
  options.rejection_threshold = perception::kLargeGrammarThreshold;
  return options;
}

perception::SynthesisOptions synthesis_options(const VoiceHostOptions& o) {
  perception::SynthesisOptions s;
  s.voice = o.voice;
  s.rate_wpm = o.rate_wpm;
  return s;
}

}  // namespace

perception::SynthesisOptions styled_voice(const perception::SynthesisOptions& base,
                                          const skills::Manager::VoiceStyle& style) {
  perception::SynthesisOptions out = base;
  out.rate_wpm = std::clamp(base.rate_wpm + 20 * style.rate_steps, 80, 450);
  out.volume = std::clamp(base.volume + base.volume / 4 * style.volume_steps, 10, 200);
  return out;
}

VoiceHost::VoiceHost(Host& host, const VoiceHostOptions& options)
    : host_(host),
      options_(options),
      own_body_(host.body()),
      light_(std::make_unique<StatusLight>(own_body_)),
      wake_word_(make_wake_word(options.wake_word, options.sensitivity)),
      recognizer_(recognizer_options()),
      synthesizer_(synthesis_options(options)) {
  data_ = host.registry().services().data;
  known_ = [this](std::string_view word) { return recognizer_.knows_word(word); };
  phrases_ = skill_phrases(host.registry());
  if (data_) values_ = current_slot_values(*data_);
  add_place_names(host.registry().services().going_places, values_);
  const perception::GrammarResult grammar = command_grammar(phrases_, values_, known_, wake_word_->keyword());
  recognizer_.set_grammar(grammar.jsgf);
  log(LogLevel::kInfo, "voice", "command grammar: " + std::to_string(grammar.templates_used) +
                                    " templates, " + std::to_string(grammar.skipped.size()) +
                                    " words left out");
  for (const std::string& skipped : grammar.skipped) log(LogLevel::kInfo, "voice", skipped);

  perception::VoiceLoopOptions loop_options;
  loop_options.endpointer = options.endpointer;
  loop_options.aligned_output = true;
  loop_ = std::make_unique<perception::VoiceLoop>(
      *wake_word_, recognizer_, synthesizer_,
      [this](const perception::Recognition& r) { return respond(r); },
      [this](std::span<const std::int16_t> chunk) {
        if (sink_) sink_(chunk);
      },
      loop_options);
  loop_->on_state([this](VoiceState state) { light_->voice(state); });
  loop_->on_turn([this](const perception::VoiceTurn& turn) {
    turns_.push_back(turn);
    if (turn.timed_out && turn.reply.text.empty()) return;
    log(LogLevel::kInfo, "voice",
        "reply ready " +
            std::to_string(std::chrono::duration_cast<std::chrono::milliseconds>(
                               turn.compute_to_first_audio)
                               .count()) +
            " ms after the endpoint, which came " +
            std::to_string((turn.endpoint_sample - turn.speech_end_sample) / 16) +
            " ms after the end of speech");
  });
  loop_->on_barge_in([this](std::int64_t) {
    if (cut_) cut_();
    host_.show("[speech cut short]");
  });

  host.on_said([this](std::string_view text) {
    std::lock_guard lock(mutex_);
    said_.emplace_back(text);
    last_said_ = text;
  });
  host.loop().on_heard([this](std::string_view text) {
    host_.show("You: " + (text.empty() ? std::string("(not understood)") : std::string(text)));
    std::lock_guard lock(mutex_);
    ++heard_;
    waiting_.reset();
  });
  host.loop().on_waiting([this](Waiting what) {
    // kCommand comes only from the loop thread between utterances, where the registry may
    // be read (a skills reload runs there too).
    std::optional<SkillPhrases> phrases;
    if (what == Waiting::kCommand) phrases = skill_phrases(host_.registry());
    std::lock_guard lock(mutex_);
    if (phrases && !(*phrases == phrases_)) {
      phrases_ = std::move(*phrases);
      phrases_changed_ = true;
    }
    if (heard_ < posted_) return;  // our utterance has not been taken yet
    if (waiting_ && what == Waiting::kAnswer && *waiting_ != Waiting::kAnswer) {
      question_later_ = true;  // a long task asked after its turn had ended
    }
    waiting_ = what;
    changed_.notify_all();
  });
  host.set_body(*light_);
  // Called on the host loop's thread; the synthesizer is the voice thread's, so the change
  // waits for apply_voice_style() there (before the reply that confirms it is spoken).
  host.manager().on_voice_style([this](skills::Manager::VoiceStyle style) {
    std::lock_guard lock(mutex_);
    voice_style_ = style;
  });
}

VoiceHost::~VoiceHost() = default;

void VoiceHost::apply_voice_style(const std::optional<skills::Manager::VoiceStyle>& style) {
  if (style) synthesizer_.set_options(styled_voice(synthesis_options(options_), *style));
}

void VoiceHost::rebuild_grammar() {
  SkillPhrases phrases = skill_phrases(host_.registry());
  std::lock_guard lock(mutex_);
  phrases_ = std::move(phrases);
  phrases_changed_ = true;
}

void VoiceHost::refresh_grammar(bool force) {
  SkillPhrases phrases;
  bool skills_changed = false;
  {
    std::lock_guard lock(mutex_);
    skills_changed = phrases_changed_;
    phrases_changed_ = false;
    phrases = phrases_;
  }
  SlotValues values = data_ ? current_slot_values(*data_) : SlotValues{};
  add_place_names(host_.registry().services().going_places, values);
  if (!force && !skills_changed && values == values_) return;
  values_ = std::move(values);
  try {
    loop_->set_command_grammar(command_grammar(phrases, values_, known_, wake_word_->keyword()).jsgf);
    log(LogLevel::kInfo, "voice", "command grammar regenerated");
  } catch (const std::exception& e) {
    log(LogLevel::kWarning, "voice", std::string("keeping the command grammar: ") + e.what());
  }
}

std::string VoiceHost::answer_grammar_for(const std::string& question) {
  SkillPhrases phrases;
  {
    std::lock_guard lock(mutex_);
    phrases = phrases_;
  }
  return answer_grammar(phrases, values_, question, known_, wake_word_->keyword());
}

perception::Reply VoiceHost::respond(const perception::Recognition& recognition) {
  // Unrecognised speech is posted as "": the manager answers it with its no-match
  // sentence, or asks its question again.
  std::string utterance = recognition.matched ? recognition.text : "";
  // The grammar lets every sentence start with the wake word (voice_grammar.h).
  const std::string prefix = wake_word_->keyword() + " ";
  if (utterance.rfind(prefix, 0) == 0) utterance.erase(0, prefix.size());
  log(LogLevel::kInfo, "voice",
      recognition.matched ? "heard \"" + recognition.text + "\" (confidence " +
                                std::to_string(recognition.confidence) + ")"
                          : "not understood: " + recognition.reason + " (confidence " +
                                std::to_string(recognition.confidence) + ")");
  {
    std::lock_guard lock(mutex_);
    ++posted_;
    waiting_.reset();
  }
  host_.loop().post(utterance);
  perception::Reply reply;
  std::string question;
  std::optional<skills::Manager::VoiceStyle> style;
  {
    std::unique_lock lock(mutex_);
    changed_.wait(lock, [&] { return (heard_ >= posted_ && waiting_) || stopping_.load(); });
    for (const std::string& sentence : said_) {
      reply.text += (reply.text.empty() ? "" : " ") + sentence;
    }
    said_.clear();
    reply.expects_answer = waiting_ == Waiting::kAnswer;
    question_later_ = false;
    question = last_said_;
    style.swap(voice_style_);
  }
  apply_voice_style(style);  // "speak slower": its "OK" already in the new voice
  if (reply.expects_answer) reply.answer_grammar = answer_grammar_for(question);
  refresh_grammar(false);  // the turn may have added a contact or a reminder
  return reply;
}

void VoiceHost::pump() {
  std::deque<std::string> said;
  bool question = false;
  bool skills_changed = false;
  std::string last;
  std::optional<skills::Manager::VoiceStyle> style;
  {
    std::lock_guard lock(mutex_);
    said.swap(said_);
    question = question_later_;
    question_later_ = false;
    skills_changed = phrases_changed_;
    last = last_said_;
    style.swap(voice_style_);
  }
  apply_voice_style(style);
  for (const std::string& sentence : said) loop_->say(sentence);
  if (skills_changed) refresh_grammar(false);
  if (question) loop_->expect_answer(answer_grammar_for(last));
}

void VoiceHost::feed(std::span<const std::int16_t> samples) {
  pump();
  loop_->feed(samples);
}

std::vector<std::int16_t> VoiceHost::run_recording(std::span<const std::int16_t> input) {
  std::vector<std::int16_t> out;
  out.reserve(input.size() + 10 * 16000);
  sink_ = [&out](std::span<const std::int16_t> chunk) {
    out.insert(out.end(), chunk.begin(), chunk.end());
  };
  constexpr std::size_t kChunk = 320;  // 20 ms, as a microphone delivers it
  for (std::size_t pos = 0; pos < input.size() && !stopping_.load(); pos += kChunk) {
    feed(input.subspan(pos, std::min(kChunk, input.size() - pos)));
  }
  pump();
  loop_->finish();
  host_.loop().close();
  sink_ = nullptr;
  return out;
}

void VoiceHost::run_live(audio::AlsaCapture& microphone, audio::AlsaPlayback& speaker) {
  sink_ = [&speaker](std::span<const std::int16_t> chunk) { speaker.write(chunk); };
  cut_ = [&speaker] { speaker.stop_now(); };
  // A little silence first, so the speaker does not starve while the first chunk is read.
  const std::vector<std::int16_t> lead(640, 0);
  speaker.write(lead);
  std::vector<std::int16_t> chunk(320);
  try {
    while (!stopping_.load()) {
      microphone.read(chunk);
      feed(chunk);
    }
  } catch (...) {
    host_.loop().close();
    sink_ = nullptr;
    cut_ = nullptr;
    throw;
  }
  host_.loop().close();
  sink_ = nullptr;
  cut_ = nullptr;
}

}  // namespace marvin::app
