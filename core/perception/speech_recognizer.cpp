#include "perception/speech_recognizer.h"

#include <stdexcept>
#include <string>

#include "perception/sphinx_decoder.h"

namespace marvin::perception {
namespace {

constexpr const char* kGrammarSearch = "commands";
constexpr const char* kPhoneLoopSearch = "phone_loop";

// The phones of the CMU dictionary (the en-us model's), each made a one-phone "word" so the
// phone loop is an ordinary grammar: pocketsphinx's own allphone search with no phone
// language model expands every triphone and runs ~25x slower on this model.
constexpr const char* kPhones[] = {"AA", "AE", "AH", "AO", "AW", "AY", "B",  "CH", "D",  "DH",
                                   "EH", "ER", "EY", "F",  "G",  "HH", "IH", "IY", "JH", "K",
                                   "L",  "M",  "N",  "NG", "OW", "OY", "P",  "R",  "S",  "SH",
                                   "T",  "TH", "UH", "UW", "V",  "W",  "Y",  "Z",  "ZH"};

}  // namespace

struct SpeechRecognizer::Impl {
  RecognizerOptions options;
  detail::Decoder grammar;
  detail::Decoder phones;
  std::string jsgf;
  int generation = 0;
  bool active = false;
  std::int64_t samples = 0;
};

SpeechRecognizer::SpeechRecognizer(const RecognizerOptions& options)
    : impl_(std::make_unique<Impl>()) {
  impl_->options = options;
  impl_->grammar = detail::make_decoder(options.model, options.decoder_settings);
  impl_->phones = detail::make_decoder(options.model, options.decoder_settings);
  // A phone loop with no phone language model: every phone sequence is equally likely.
  std::string loop = "#JSGF V1.0;\ngrammar phones;\npublic <loop> = <phone>+;\n<phone> = ";
  bool first = true;
  for (const char* phone : kPhones) {
    std::string word = "phone_";
    for (const char* c = phone; *c != '\0'; ++c) word += static_cast<char>(*c - 'A' + 'a');
    if (ps_add_word(impl_->phones.get(), word.c_str(), phone, FALSE) < 0) continue;
    loop += (first ? "" : " | ") + word;
    first = false;
  }
  loop += ";\n";
  if (first || ps_set_jsgf_string(impl_->phones.get(), kPhoneLoopSearch, loop.c_str()) < 0 ||
      ps_set_search(impl_->phones.get(), kPhoneLoopSearch) < 0) {
    throw std::runtime_error("pocketsphinx: cannot create the phone loop for " +
                             options.model.acoustic_model.string());
  }
}

SpeechRecognizer::~SpeechRecognizer() {
  if (impl_->active) {
    ps_end_utt(impl_->grammar.get());
    ps_end_utt(impl_->phones.get());
  }
}

void SpeechRecognizer::set_grammar(const std::string& jsgf) {
  if (impl_->active) throw std::logic_error("SpeechRecognizer::set_grammar during an utterance");
  if (jsgf == impl_->jsgf) return;
  // Each grammar gets a fresh search name, so a refused one leaves the current in place.
  const std::string name = std::string(kGrammarSearch) + std::to_string(impl_->generation + 1);
  if (ps_set_jsgf_string(impl_->grammar.get(), name.c_str(), jsgf.c_str()) < 0) {
    throw std::runtime_error("pocketsphinx refused the command grammar (syntax error or a word "
                             "missing from " + impl_->options.model.dictionary.string() + ")");
  }
  if (ps_set_search(impl_->grammar.get(), name.c_str()) < 0) {
    throw std::runtime_error("pocketsphinx cannot select the command grammar");
  }
  if (impl_->generation > 0) {
    const std::string old = std::string(kGrammarSearch) + std::to_string(impl_->generation);
    ps_unset_search(impl_->grammar.get(), old.c_str());
  }
  ++impl_->generation;
  impl_->jsgf = jsgf;
}

bool SpeechRecognizer::has_grammar() const { return impl_->generation > 0; }

const std::string& SpeechRecognizer::grammar() const { return impl_->jsgf; }

bool SpeechRecognizer::knows_word(std::string_view word) const {
  const std::string w(word);
  return ps_lookup_word(impl_->grammar.get(), w.c_str()) != nullptr;
}

bool SpeechRecognizer::in_utterance() const { return impl_->active; }

void SpeechRecognizer::begin() {
  if (!has_grammar()) throw std::logic_error("SpeechRecognizer::begin without a grammar");
  if (impl_->active) end();
  if (ps_start_utt(impl_->grammar.get()) < 0 || ps_start_utt(impl_->phones.get()) < 0) {
    throw std::runtime_error("pocketsphinx: cannot start an utterance");
  }
  impl_->active = true;
  impl_->samples = 0;
}

void SpeechRecognizer::feed(std::span<const std::int16_t> samples) {
  if (!impl_->active || samples.empty()) return;
  if (ps_process_raw(impl_->grammar.get(), samples.data(), samples.size(), FALSE, FALSE) < 0 ||
      ps_process_raw(impl_->phones.get(), samples.data(), samples.size(), FALSE, FALSE) < 0) {
    throw std::runtime_error("pocketsphinx: decoding failed");
  }
  impl_->samples += static_cast<std::int64_t>(samples.size());
}

Recognition SpeechRecognizer::end() {
  Recognition result;
  if (!impl_->active) {
    result.reason = "no utterance";
    return result;
  }
  impl_->active = false;
  ps_end_utt(impl_->grammar.get());
  ps_end_utt(impl_->phones.get());
  result.samples = impl_->samples;
  const int frames = ps_get_n_frames(impl_->grammar.get());
  int32 grammar_score = 0;
  const char* hyp = ps_get_hyp(impl_->grammar.get(), &grammar_score);
  int32 phone_score = 0;
  ps_get_hyp(impl_->phones.get(), &phone_score);
  std::string text;
  if (hyp != nullptr) {
    for (const char* c = hyp; *c != '\0'; ++c) {
      if (*c == ' ' && (text.empty() || text.back() == ' ')) continue;
      text += *c;
    }
    while (!text.empty() && text.back() == ' ') text.pop_back();
  }
  if (text.empty() || frames <= 0) {
    result.reason = "no sentence of the grammar fits the audio";
    return result;
  }
  result.confidence =
      static_cast<float>(grammar_score - phone_score) / static_cast<float>(frames);
  result.text = text;
  if (result.confidence < impl_->options.rejection_threshold) {
    result.reason = "best sentence \"" + text + "\" fits the audio too poorly (confidence " +
                    std::to_string(result.confidence) + ")";
    result.text.clear();
    return result;
  }
  result.matched = true;
  return result;
}

Recognition SpeechRecognizer::recognize(std::span<const std::int16_t> samples) {
  begin();
  feed(samples);
  return end();
}

}  // namespace marvin::perception
