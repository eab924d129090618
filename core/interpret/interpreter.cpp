#include "interpret/interpreter.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <mutex>
#include <set>
#include <unordered_map>

#include "interpret/builtins.h"
#include "interpret/intent_model.h"
#include "interpret/intent_table.h"
#include "interpret/matcher.h"
#include "interpret/normalizer.h"
#include "interpret/phrasing.h"
#include "interpret/slot_parsers.h"
#include "interpret/slot_plausibility.h"
#include "interpret/template.h"
#include "interpret/tolerant_matcher.h"
#include "interpret/wordnet.h"

namespace marvin::interpret {
namespace {

constexpr std::array<std::pair<SlotType, const char*>, 6> kSlotTypeNames{{
    {SlotType::kNumber, "number"},
    {SlotType::kDuration, "duration"},
    {SlotType::kDateTime, "datetime"},
    {SlotType::kContact, "contact"},
    {SlotType::kList, "list"},
    {SlotType::kText, "text"},
}};

// A dialogue answer in other words is short; the model must be this sure of it.
constexpr std::size_t kMaxDialogueWords = 12;
constexpr float kDialogueProbability = 0.5F;

// Longer utterances are never a request (a 1 MB line is answered at once).
constexpr std::size_t kMaxExactWords = 64;
// No request said or typed is longer: 64 words of 64 bytes. A longer line (a pasted file, a
// stuck key) is refused before it is normalised, which would otherwise cost time in
// proportion to its length on every turn it is tried (builtin(), then understand()).
constexpr std::size_t kMaxUtteranceBytes = 4096;

// Words a dialogue answer may start with before the value: "it's eight", "to Anna".
constexpr std::array<std::string_view, 9> kAnswerFillers{"it's", "it",  "is",    "its", "to",
                                                         "for",  "the", "about", "call"};

// A dialogue answer may say more than an utterance's text slot.
constexpr std::size_t kAnswerTextMaxWords = 24;

class IntentSlotReader final : public SlotReader {
 public:
  IntentSlotReader(const CompiledIntent& intent, const Context& context,
                   const ContactBook& contacts, TimeCue cue)
      : intent_(intent), context_(context), contacts_(contacts), cue_(cue) {}

  std::optional<SlotValue> read(int slot, std::span<const std::string> words) const override {
    return read_slot_value(intent_.slots[static_cast<std::size_t>(slot)], words, context_,
                           contacts_, kTextSlotMaxWords, cue_);
  }
  bool is_text(int slot) const override {
    return intent_.slots[static_cast<std::size_t>(slot)].spec.type == SlotType::kText;
  }
  std::size_t max_words(int slot) const override {
    return intent_.slots[static_cast<std::size_t>(slot)].max_words;
  }

 private:
  const CompiledIntent& intent_;
  const Context& context_;
  const ContactBook& contacts_;
  const TimeCue cue_;
};

std::string template_error(const IntentSpec& spec, std::string_view text, std::size_t column,
                           const std::string& message) {
  return "skill \"" + spec.skill_id + "\", intent \"" + spec.intent + "\", template \"" +
         std::string(text) + "\": column " + std::to_string(column) + ": " + message;
}

std::string intent_error(const IntentSpec& spec, const std::string& message) {
  return "skill \"" + spec.skill_id + "\", intent \"" + spec.intent + "\": " + message;
}

}  // namespace

const char* to_string(SlotType type) {
  for (const auto& [value, name] : kSlotTypeNames) {
    if (value == type) return name;
  }
  return "text";
}

std::optional<SlotType> slot_type_from_string(std::string_view name) {
  for (const auto& [value, type_name] : kSlotTypeNames) {
    if (name == type_name) return value;
  }
  return std::nullopt;
}

// The model and the tables tolerant matching needs, built from the registered intents.
struct ModelState {
  IntentModel model;
  std::vector<std::string> word_stems;  // vocabulary id -> stem
  std::vector<SynonymTable> synonyms;   // per intent (same order as Impl::intents)
  // Example sentences of intents without slots, as the model sees them (politeness
  // stripped, words joined by spaces) -> intent index, or kSharedExample when two intents
  // give the same sentence.
  std::unordered_map<std::string, std::size_t> slotless_examples;
  static constexpr std::size_t kSharedExample = static_cast<std::size_t>(-1);
  int none_class = 0;  // the out-of-scope class (= number of intents)
  // Then the dialogue answers: none_class + 1, + 2, + 3.
  static constexpr std::array<Builtin, 3> kDialogue{Builtin::kYes, Builtin::kNo, Builtin::kRepeat};
};

struct Interpreter::Impl {
  Vocabulary vocabulary;
  std::vector<CompiledIntent> intents;
  // Built on first use after a change; immutable once built, so readers share it.
  mutable std::mutex model_mutex;
  mutable std::shared_ptr<const ModelState> model;

  Impl() = default;
  Impl(const Impl& other)
      : vocabulary(other.vocabulary), intents(other.intents), model(other.current_model()) {}

  std::shared_ptr<const ModelState> current_model() const {
    std::lock_guard lock(model_mutex);
    return model;
  }
  std::shared_ptr<const ModelState> ensure_model() const;
  void invalidate() {
    std::lock_guard lock(model_mutex);
    model.reset();
  }

  // The best exact match of each intent (empty optional where none).
  std::vector<std::optional<TemplateMatch>> exact_matches(const std::vector<std::string>& words,
                                                          const Context& context) const;
  Match to_match(const CompiledIntent& intent, std::vector<SlotCapture> captures) const;

  // True when every template of intent `k` has a slot naming a person or thing.
  bool needs_entity(std::size_t k) const {
    const CompiledIntent& intent = intents[k];
    return std::all_of(
        intent.templates.begin(), intent.templates.end(), [&](const CompiledTemplate& t) {
          return std::any_of(t.program.begin(), t.program.end(), [&](const Instruction& in) {
            return in.op == Instruction::Op::kSlot &&
                   intent.slots[static_cast<std::size_t>(in.a)].entity;
          });
        });
  }
  // True when `parse` fills a person-or-thing slot of intent `k` with a known contact or
  // words that name one without the benefit of the doubt (slot_plausibility.h, strict).
  // With `contacts_only`, only a known contact counts.
  bool fills_entity_strictly(std::size_t k, const TolerantMatch& parse, const ContactBook& contacts,
                             bool contacts_only) const {
    return std::any_of(parse.slots.begin(), parse.slots.end(), [&](const SlotCapture& c) {
      if (!intents[k].slots[static_cast<std::size_t>(c.slot)].entity) return false;
      const std::vector<std::string> words = normalize(c.value.text);
      return contacts.find(words).has_value() ||
             (!contacts_only && plausible_entity(words, WordNet::installed(), /*strict=*/true));
    });
  }
  // True when `parse` fills one of intent `k`'s person-or-thing slots.
  bool fills_entity(std::size_t k, const std::optional<TolerantMatch>& parse) const {
    if (!parse) return false;
    return std::any_of(parse->slots.begin(), parse->slots.end(), [&](const SlotCapture& c) {
      return intents[k].slots[static_cast<std::size_t>(c.slot)].entity;
    });
  }
};

Interpreter::Interpreter() : impl_(std::make_unique<Impl>()) {}
Interpreter::~Interpreter() = default;
Interpreter::Interpreter(const Interpreter& other) : impl_(std::make_unique<Impl>(*other.impl_)) {}
Interpreter& Interpreter::operator=(const Interpreter& other) {
  if (this != &other) impl_ = std::make_unique<Impl>(*other.impl_);
  return *this;
}
Interpreter::Interpreter(Interpreter&& other) noexcept
    : impl_(std::exchange(other.impl_, std::make_unique<Impl>())) {}
Interpreter& Interpreter::operator=(Interpreter&& other) noexcept {
  std::swap(impl_, other.impl_);
  return *this;
}

void Interpreter::add(const IntentSpec& spec) {
  if (spec.skill_id.empty()) throw TemplateError(intent_error(spec, "empty skill id"));
  if (spec.intent.empty()) throw TemplateError(intent_error(spec, "empty intent name"));
  if (spec.templates.empty()) throw TemplateError(intent_error(spec, "no templates"));

  CompiledIntent intent;
  intent.spec = spec;
  std::vector<std::string> names;
  std::vector<std::size_t> max_words;
  std::set<std::string> seen;
  for (const SlotSpec& slot : spec.slots) {
    if (slot.name.empty()) throw TemplateError(intent_error(spec, "a slot has no name"));
    if (!seen.insert(slot.name).second) {
      throw TemplateError(intent_error(spec, "slot \"" + slot.name + "\" is declared twice"));
    }
    if (slot.type == SlotType::kList) {
      if (slot.values.empty()) {
        throw TemplateError(intent_error(spec, "list slot \"" + slot.name + "\" has no values"));
      }
      for (const std::string& value : slot.values) {
        if (normalize(value).empty()) {
          throw TemplateError(intent_error(
              spec,
              "list slot \"" + slot.name + "\" has a value without words: \"" + value + "\""));
        }
      }
    }
    intent.slots.push_back(prepare_slot(slot));
    names.push_back(slot.name);
    max_words.push_back(intent.slots.back().max_words);
  }

  // Compile into a copy of the vocabulary so a failure leaves the interpreter unchanged.
  Vocabulary vocabulary = impl_->vocabulary;
  for (const std::string& text : spec.templates) {
    CompiledTemplate compiled;
    TemplateSyntaxError error;
    if (!compile_template(text, names, max_words, vocabulary, compiled, error)) {
      throw TemplateError(template_error(spec, text, error.column, error.message));
    }
    intent.templates.push_back(std::move(compiled));
  }
  impl_->vocabulary = std::move(vocabulary);
  impl_->intents.push_back(std::move(intent));
  impl_->invalidate();
}

std::size_t Interpreter::remove_skill(std::string_view skill_id) {
  auto& intents = impl_->intents;
  std::size_t before = intents.size();
  std::erase_if(intents, [&](const CompiledIntent& i) { return i.spec.skill_id == skill_id; });
  impl_->invalidate();
  return before - intents.size();
}

std::size_t Interpreter::size() const { return impl_->intents.size(); }

std::vector<std::string> Interpreter::conflicts() const {
  return find_conflicts(impl_->intents, impl_->vocabulary);
}

namespace {

// True when one of the first two verb senses of `word`, or what they are a kind of, is a
// sense of "stop" or "cancel" in WordNet. Only verbs: "stop" the noun is a bus stop.
bool means_stop(const std::string& word) {
  const WordNet* wordnet = WordNet::installed();
  if (wordnet == nullptr || word.size() < 3) return false;
  static const std::vector<std::string> kStopSenses = [wordnet] {
    std::vector<std::string> senses;
    for (const char* w : {"stop", "cancel", "halt", "abort"}) {
      for (std::string& c : wordnet->verb_concepts(w, 3, 0)) senses.push_back(std::move(c));
    }
    std::sort(senses.begin(), senses.end());
    return senses;
  }();
  for (const std::string& c : wordnet->verb_concepts(word, 2, 2)) {
    if (std::binary_search(kStopSenses.begin(), kStopSenses.end(), c)) return true;
  }
  return false;
}

}  // namespace

Builtin Interpreter::builtin(std::string_view utterance) const {
  if (utterance.size() > kMaxUtteranceBytes) return Builtin::kNone;
  Builtin fixed = classify_builtin(utterance);
  if (fixed != Builtin::kNone) return fixed;
  // Yes, no and repeat said in other words ("you got it", "i didn't catch that"): when the
  // model is sure. Stop is never guessed: only its fixed words stop things.
  std::vector<std::string> words = normalize(utterance);
  if (words.empty() || words.size() > kMaxDialogueWords) return Builtin::kNone;
  std::vector<std::string> request = strip_politeness(words);
  // One word that WordNet files under stopping or cancelling ("cease", "terminate",
  // "rescind"): a fixed lexicon, not a guess.
  if (request.size() == 1 && means_stop(request[0])) return Builtin::kStop;
  // "yes no" is neither: an answer holding both is never guessed.
  const bool has_yes = std::find(request.begin(), request.end(), "yes") != request.end();
  const bool has_no = std::find(request.begin(), request.end(), "no") != request.end();
  if (has_yes && has_no) return Builtin::kNone;
  // A question ("is it true that ...", "do you agree") asks; it does not answer yes or no.
  const bool question =
      !request.empty() &&
      (request[0] == "is" || request[0] == "are" || request[0] == "was" || request[0] == "were" ||
       request[0] == "do" || request[0] == "does" || request[0] == "did" || request[0] == "am");
  std::shared_ptr<const ModelState> state = impl_->ensure_model();
  std::vector<float> p = state->model.probabilities(request);
  const auto top = static_cast<std::size_t>(std::max_element(p.begin(), p.end()) - p.begin());
  const auto first = static_cast<std::size_t>(state->none_class) + 1;
  float runner_up = 0;  // the likeliest other dialogue answer ("yes no" is neither)
  for (std::size_t k = first; k < first + ModelState::kDialogue.size(); ++k) {
    if (k != top) runner_up = std::max(runner_up, p[k]);
  }
  if (top >= first && top < first + ModelState::kDialogue.size() &&
      p[top] >= kDialogueProbability && p[top] >= 2 * runner_up) {
    const Builtin answer = ModelState::kDialogue[top - first];
    if (question && answer != Builtin::kRepeat) return Builtin::kNone;
    return answer;
  }
  return Builtin::kNone;
}

std::optional<Match> Interpreter::match(std::string_view utterance, const Context& context) const {
  Understanding u = understand(utterance, context);
  if (u.outcome == Understanding::Outcome::kMatch) return std::move(u.match);
  return std::nullopt;
}

std::optional<Match> Interpreter::match_exact(std::string_view utterance,
                                              const Context& context) const {
  if (utterance.size() > kMaxUtteranceBytes) return std::nullopt;
  std::vector<std::string> words = normalize(utterance);
  if (words.size() > kMaxExactWords) return std::nullopt;
  std::size_t skip = 0;
  if (words.size() >= 2 && (words[0] == "hey" || words[0] == "ok" || words[0] == "okay") &&
      words[1] == "marvin") {
    skip = 2;
  } else if (!words.empty() && words[0] == "marvin") {
    skip = 1;
  }
  words.erase(words.begin(), words.begin() + static_cast<std::ptrdiff_t>(skip));
  for (int attempt = 0; attempt < 2; ++attempt) {
    auto exact = impl_->exact_matches(words, context);
    std::optional<std::size_t> best;
    for (std::size_t k = 0; k < exact.size(); ++k) {
      if (exact[k] && (!best || ranks_above(*exact[k], *exact[*best]))) best = k;
    }
    if (best) {
      Match m = impl_->to_match(impl_->intents[*best], std::move(exact[*best]->slots));
      m.literal_words = exact[*best]->literal_words;
      return m;
    }
    bool changed = false;
    if (words.size() >= 2 && words.front() == "please") {
      words.erase(words.begin());
      changed = true;
    }
    if (words.size() >= 2 && words.back() == "please") {
      words.pop_back();
      changed = true;
    }
    if (!changed) break;
  }
  return std::nullopt;
}

std::optional<SlotValue> Interpreter::parse_slot(const SlotSpec& slot, std::string_view answer,
                                                 const Context& context,
                                                 std::string_view request) const {
  PreparedSlot prepared = prepare_slot(slot);
  ContactBook contacts(context.contact_names);
  const TimeCue cue =
      request.size() > kMaxUtteranceBytes ? TimeCue{} : time_cue(normalize(request));
  std::vector<std::string> words = normalize(answer);
  if (words.size() >= 2 && words.back() == "please") words.pop_back();
  std::size_t begin = 0;
  // Try the answer as given, then without up to two leading fillers ("it's", "to", ...).
  for (int attempt = 0; attempt < 3 && begin < words.size(); ++attempt) {
    std::span<const std::string> span(words.data() + begin, words.size() - begin);
    if (auto value = read_slot_value(prepared, span, context, contacts, kAnswerTextMaxWords, cue)) {
      return value;
    }
    if (std::find(kAnswerFillers.begin(), kAnswerFillers.end(), words[begin]) ==
        kAnswerFillers.end()) {
      break;
    }
    ++begin;
  }
  return std::nullopt;
}

// ---------------------------------------------------------------------------------------
// Understanding requests as people say them: the intent model and tolerant matching.

namespace {

constexpr std::size_t kMaxUnderstoodWords = 64;
// Training sentences drawn from one intent's templates (spread over its templates).
constexpr std::size_t kExpansionsPerIntent = 96;
constexpr std::size_t kMinExpansionsPerTemplate = 6;
constexpr std::size_t kMaxExpansionsPerTemplate = 24;
constexpr std::size_t kTolerantCandidates = 3;
// Decision thresholds, measured on requests written by other people (core/interpret/README.md).
constexpr float kAcceptProbability = 0.4F;
constexpr float kNoneRatio = 2.0F;  // the top intent must be twice as likely as out of scope
constexpr float kAcceptWithTemplate = 0.12F;  // when a template parses at a low cost
constexpr float kNoneRatioWithTemplate = 0.25F;
// The same for an intent with templates only (no examples): the model knows it only through
// its template expansions, so its probability stays lower and moves with every other skill's
// examples; its template fit is most of its evidence. (At 0.12 like the others, "do you know
// where my keys are" for where-is's "where (is|are) my {item}" came and went at about 0.12
// as other skills added templates; the development set reads the same at 0.1 and 0.12.)
constexpr float kNoneRatioTemplateOnly = 0.2F;
constexpr float kAcceptTemplateOnly = 0.1F;
constexpr float kLowTemplateCost = 1.5F;
// The reasons of the two word-for-word decisions; understand() tells them apart from the
// model's by these.
constexpr const char* kExactTemplate = "template matches word for word";
constexpr const char* kExactExample = "an example sentence word for word";
// Lead-ins are looked for in utterances of at most this many words (each split is a whole
// understanding: a long monologue is not a lead-in and a request).
constexpr std::size_t kMaxLeadInWords = 24;
constexpr float kAskEach = 0.2F;
constexpr float kAskTogether = 0.5F;
// An accepted intent whose runner-up is this close is asked about instead.
constexpr float kCloseCall = 0.8F;
// A skill whose intents together are this likely (and kNoneRatio x out of scope) is meant
// even when the model splits its belief among them ("secure the doors": on, off or query).
constexpr float kSkillProbability = 0.35F;
constexpr float kSkillShare = 0.05F;
constexpr float kModelOverridesExact = 0.3F;
// Template costs above which an intent that needs a person or thing wants one named for
// sure (understand()): a contact or a thing without the benefit of the doubt, and above the
// second only a contact.
constexpr float kLooseEntityTemplateCost = 2.5F;
constexpr float kVeryLooseEntityTemplateCost = 3.5F;

// Words people use for the words templates are written with; any skill benefits.
// utterance word -> template words it may stand for.
const std::vector<std::pair<std::string, std::vector<std::string>>>& builtin_synonyms() {
  static const std::vector<std::pair<std::string, std::vector<std::string>>> table{
      {"show", {"tell"}},
      {"give", {"tell"}},
      {"say", {"tell"}},
      {"read", {"tell"}},
      {"delete", {"cancel", "remove"}},
      {"remove", {"cancel", "delete"}},
      {"erase", {"cancel", "delete", "remove"}},
      {"clear", {"cancel", "delete", "remove"}},
      {"cancel", {"delete", "remove"}},
      {"create", {"set", "add", "make"}},
      {"make", {"set", "add"}},
      {"start", {"set"}},
      {"put", {"add", "set"}},
      {"schedule", {"set", "add"}},
      {"calendar", {"schedule"}},
      {"agenda", {"schedule"}},
      {"diary", {"schedule"}},
      {"planner", {"schedule"}},
      {"lamp", {"light"}},
      {"lights", {"light"}},
      {"hi", {"hello"}},
      {"hey", {"hello"}},
      {"today's", {"today"}},
      {"current", {"the"}},
      {"which", {"what"}},
  };
  return table;
}

std::string join_words(const std::vector<std::string>& words) {
  std::string out;
  for (const std::string& w : words) {
    if (!out.empty()) out.push_back(' ');
    out += w;
  }
  return out;
}

// Sample words for a slot when expanding templates into training sentences.
std::vector<std::vector<std::string>> slot_samples(const PreparedSlot& slot) {
  static const std::array<const char*, 9> kWhen{"tomorrow at 8 am", "at 6 pm",       "on monday",
                                                "tonight",          "in 20 minutes", "at noon",
                                                "every day at 9",   "next friday",   "at 7:30"};
  static const std::array<const char*, 5> kDuration{"10 minutes", "an hour", "30 seconds",
                                                    "2 hours", "5 minutes"};
  static const std::array<const char*, 4> kText{"something", "the thing", "it", "that"};
  std::vector<std::vector<std::string>> out;
  switch (slot.spec.type) {
    case SlotType::kDateTime:
      for (const char* w : kWhen) out.push_back(normalize(w));
      break;
    case SlotType::kDuration:
      for (const char* w : kDuration) out.push_back(normalize(w));
      break;
    case SlotType::kNumber:
      out.push_back({"3"});
      out.push_back({"10"});
      break;
    case SlotType::kContact:
      out.push_back({"anna"});
      out.push_back({"my", "son"});
      break;
    case SlotType::kList:
      for (const std::string& v : slot.spec.values) out.push_back(normalize(v));
      break;
    case SlotType::kText:
      for (const char* w : kText) out.push_back(normalize(w));
      break;
  }
  return out;
}

// Sentences a compiled template produces: alternatives and optionals both ways, slots filled
// with samples; at most `limit`, varied by taking alternatives in a rotating order.
class TemplateExpander {
 public:
  TemplateExpander(const CompiledTemplate& compiled, const std::vector<std::string>& words_by_id,
                   const std::vector<std::vector<std::vector<std::string>>>& samples,
                   std::size_t limit)
      : program_(compiled.program), words_by_id_(words_by_id), samples_(samples), limit_(limit) {}

  std::vector<std::vector<std::string>> run() {
    walk(0);
    return std::move(out_);
  }

 private:
  void walk(int pc) {
    if (out_.size() >= limit_ || ++steps_ > 4000) return;
    const Instruction& in = program_[static_cast<std::size_t>(pc)];
    switch (in.op) {
      case Instruction::Op::kWord:
        current_.push_back(words_by_id_[static_cast<std::size_t>(in.a)]);
        walk(pc + 1);
        current_.pop_back();
        return;
      case Instruction::Op::kJump:
        walk(in.a);
        return;
      case Instruction::Op::kSplit:
        if ((turn_++ & 1U) == 0) {
          walk(in.a);
          walk(in.b);
        } else {
          walk(in.b);
          walk(in.a);
        }
        return;
      case Instruction::Op::kSlot: {
        const auto& options = samples_[static_cast<std::size_t>(in.a)];
        if (options.empty()) return;
        const auto& sample = options[(sample_turn_++) % options.size()];
        std::size_t size = current_.size();
        current_.insert(current_.end(), sample.begin(), sample.end());
        walk(pc + 1);
        current_.resize(size);
        return;
      }
      case Instruction::Op::kMatch:
        out_.push_back(current_);
        return;
    }
  }

  const std::vector<Instruction>& program_;
  const std::vector<std::string>& words_by_id_;
  const std::vector<std::vector<std::vector<std::string>>>& samples_;
  std::size_t limit_;
  std::vector<std::string> current_;
  std::vector<std::vector<std::string>> out_;
  unsigned turn_ = 0;
  std::size_t sample_turn_ = 0;
  int steps_ = 0;
};

// `sentence` with each single-word synonym of the intent put in for its word, one variant
// per synonym (at most a few).
void add_synonym_variants(
    const std::vector<std::string>& sentence,
    const std::vector<std::pair<std::string, std::vector<std::string>>>& synonyms, int label,
    std::vector<LabelledSentence>& out) {
  int added = 0;
  for (const auto& [word, alternatives] : synonyms) {
    std::vector<std::string> key = normalize(word);
    if (key.size() != 1) continue;
    for (std::size_t i = 0; i < sentence.size(); ++i) {
      if (sentence[i] != key[0]) continue;
      for (const std::string& alternative : alternatives) {
        if (added >= 4) return;
        std::vector<std::string> variant(sentence.begin(),
                                         sentence.begin() + static_cast<std::ptrdiff_t>(i));
        for (std::string& w : normalize(alternative)) variant.push_back(std::move(w));
        variant.insert(variant.end(), sentence.begin() + static_cast<std::ptrdiff_t>(i) + 1,
                       sentence.end());
        out.push_back({std::move(variant), label});
        ++added;
      }
      break;
    }
  }
}

}  // namespace

std::shared_ptr<const ModelState> Interpreter::Impl::ensure_model() const {
  std::lock_guard lock(model_mutex);
  if (model) return model;
  auto state = std::make_shared<ModelState>();
  std::vector<std::string> words_by_id(vocabulary.size());
  vocabulary.for_each(
      [&](const std::string& word, int id) { words_by_id[static_cast<std::size_t>(id)] = word; });
  state->word_stems.reserve(words_by_id.size());
  for (const std::string& w : words_by_id) state->word_stems.push_back(stem(w));

  std::vector<LabelledSentence> sentences;
  for (std::size_t i = 0; i < intents.size(); ++i) {
    const CompiledIntent& intent = intents[i];
    const int label = static_cast<int>(i);
    // Synonyms: the built-in ones, then the skill's (utterance word -> template word ids).
    SynonymTable table;
    auto add_synonym = [&](const std::string& said, const std::string& written) {
      std::vector<std::string> s = normalize(said);
      std::vector<std::string> w = normalize(written);
      if (s.size() != 1 || w.size() != 1) return;
      int id = vocabulary.find(w[0]);
      if (id != Vocabulary::kUnknown) table[s[0]].push_back(id);
    };
    for (const auto& [said, written] : builtin_synonyms()) {
      for (const std::string& w : written) add_synonym(said, w);
    }
    for (const auto& [written, saids] : intent.spec.synonyms) {
      for (const std::string& said : saids) add_synonym(said, written);
    }
    state->synonyms.push_back(std::move(table));

    std::vector<std::vector<std::vector<std::string>>> samples;
    for (const PreparedSlot& slot : intent.slots) samples.push_back(slot_samples(slot));
    const std::size_t per_template =
        std::clamp(kExpansionsPerIntent / intent.templates.size(), kMinExpansionsPerTemplate,
                   kMaxExpansionsPerTemplate);
    for (const CompiledTemplate& compiled : intent.templates) {
      for (auto& sentence : TemplateExpander(compiled, words_by_id, samples, per_template).run()) {
        // Trained on what understand() will look at: the request without politeness.
        std::vector<std::string> request = strip_politeness(sentence);
        add_synonym_variants(request, intent.spec.synonyms, label, sentences);
        sentences.push_back({std::move(request), label});
      }
    }
    for (const std::string& example : intent.spec.examples) {
      std::vector<std::string> words = strip_politeness(normalize(example));
      if (intent.spec.slots.empty() && !words.empty()) {
        // An example two intents share decides nothing: the model ranks them (and asks).
        auto [at, added] = state->slotless_examples.emplace(join_words(words), i);
        if (!added && at->second != i) at->second = ModelState::kSharedExample;
      }
      add_synonym_variants(words, intent.spec.synonyms, label, sentences);
      sentences.push_back({std::move(words), label});
    }
  }
  state->none_class = static_cast<int>(intents.size());
  for (const std::string& text : background_sentences()) {
    sentences.push_back({strip_politeness(normalize(text)), state->none_class});
  }
  for (std::size_t d = 0; d < ModelState::kDialogue.size(); ++d) {
    for (const std::string& text : dialogue_sentences(ModelState::kDialogue[d])) {
      sentences.push_back(
          {strip_politeness(normalize(text)), state->none_class + 1 + static_cast<int>(d)});
    }
  }
  state->model = IntentModel::train(
      sentences, state->none_class + 1 + static_cast<int>(ModelState::kDialogue.size()),
      WordNet::installed());
  model = std::move(state);
  return model;
}

std::size_t Interpreter::build_model() const { return impl_->ensure_model()->model.memory_bytes(); }

std::vector<std::optional<TemplateMatch>> Interpreter::Impl::exact_matches(
    const std::vector<std::string>& words, const Context& context) const {
  std::vector<std::optional<TemplateMatch>> found(intents.size());
  if (words.empty()) return found;
  std::vector<int> ids(words.size());
  std::vector<char> present(vocabulary.size(), 0);
  for (std::size_t i = 0; i < words.size(); ++i) {
    ids[i] = vocabulary.find(words[i]);
    if (ids[i] != Vocabulary::kUnknown) present[static_cast<std::size_t>(ids[i])] = 1;
  }
  ContactBook contacts(context.contact_names);
  const TimeCue cue = time_cue(words);
  for (std::size_t k = 0; k < intents.size(); ++k) {
    const CompiledIntent& intent = intents[k];
    IntentSlotReader reader(intent, context, contacts, cue);
    for (const CompiledTemplate& compiled : intent.templates) {
      if (words.size() < compiled.min_words || words.size() > compiled.max_words) continue;
      bool has_all =
          std::all_of(compiled.required_words.begin(), compiled.required_words.end(),
                      [&](int id) { return present[static_cast<std::size_t>(id)] != 0; });
      if (!has_all) continue;
      auto m = match_template(compiled, words, ids, reader);
      if (m && (!found[k] || ranks_above(*m, *found[k]))) found[k] = std::move(m);
    }
  }
  return found;
}

Match Interpreter::Impl::to_match(const CompiledIntent& intent,
                                  std::vector<SlotCapture> captures) const {
  Match match;
  match.skill_id = intent.spec.skill_id;
  match.intent = intent.spec.intent;
  for (SlotCapture& capture : captures) {
    match.slots[intent.slots[static_cast<std::size_t>(capture.slot)].spec.name] =
        std::move(capture.value);
  }
  return match;
}

namespace {

// Whether `lead` (the words before a request) may simply be dropped: a remark or a reason
// ("I'm going to bed", "it's getting late", "oh dear") and not something that changes what
// the request means: a negation ("I don't want you to"), a question about it ("how do I",
// "should I"), a condition or a time ("if", "when", "after dinner"), or someone else's words
// ("ask Anna to", "she said").
bool droppable_lead_in(std::span<const std::string> lead) {
  // Negation, condition, time, question and reported words anywhere in the lead-in.
  static const std::set<std::string, std::less<>> kNever = {
      "not", "never", "dont",                                                   // negation
      "if", "unless", "when", "whenever", "once", "before", "after", "until",   // condition
      "while", "because",
      "later", "tomorrow", "tonight", "minute", "minutes", "hour", "hours",     // time
      "o'clock", "pm", "noon", "midnight", "every", "morning", "afternoon", "evening",
      "monday", "tuesday", "wednesday", "thursday", "friday", "saturday", "sunday",
      "how", "whether", "why", "what",                                          // question
      "tell", "ask", "asked", "said", "says", "told", "remind", "reminder",     // reported
      "remember"};
  // A question starts so ("do you think I should ...", "can I ...").
  static const std::set<std::string, std::less<>> kNotFirst = {
      "do",    "does", "did",   "is",   "are",   "was",   "were",  "should", "shall", "can",
      "could", "would", "will", "may",  "might", "must",  "where", "who",    "which", "have",
      "has",   "had"};
  // A lead-in is a whole clause: it does not end on a subject, an article or a conjunction
  // ("then I | turn off ...", "so you | ...").
  static const std::set<std::string, std::less<>> kNotLast = {
      "i", "we", "he", "she", "they", "and", "or", "the", "a", "my", "please", "just"};
  if (lead.size() < 2) return false;
  if (kNotFirst.count(lead.front()) || kNotLast.count(lead.back())) return false;
  // A number is a time or an amount the request would need ("in 5 minutes", "at 8").
  return std::none_of(lead.begin(), lead.end(), [](const std::string& w) {
    return kNever.count(w) > 0 || std::isdigit(static_cast<unsigned char>(w[0]));
  });
}

}  // namespace

Understanding Interpreter::understand(std::string_view utterance, const Context& context) const {
  Understanding whole = understand_whole(utterance, context);
  const std::vector<std::string>& r = whole.request;
  const bool negated = (r.size() >= 3 && r[0] == "do" && r[1] == "not") ||
                       (r.size() >= 2 && (r[0] == "never" || r[0] == "dont"));
  const bool said_word_for_word = whole.reason == kExactTemplate || whole.reason == kExactExample;
  // An intent whose own template says the same negation of the same verb knows what it
  // means: "(do not|never) let me forget (to|about) {task}" fits "don't let me forget the
  // bins" (not "don't remind me about my pills").
  const std::size_t verb_at = negated ? (r[0] == "do" ? 2 : 1) : 0;
  auto says_not = [&](const Match& m) {
    for (const CompiledIntent& intent : impl_->intents) {
      if (intent.spec.skill_id != m.skill_id || intent.spec.intent != m.intent) continue;
      for (const std::string& t : intent.spec.templates) {
        const std::vector<std::string> w = normalize(t);
        for (std::size_t i = 0; i + 1 < w.size(); ++i) {
          if (w[i] != "not" && w[i] != "never") continue;
          std::size_t v = i + 1;
          while (v < w.size() && (w[v] == "not" || w[v] == "never")) ++v;  // "(do not|never)"
          if (v < w.size() && w[v] == r[verb_at]) return true;
        }
      }
    }
    return false;
  };
  if (negated && !(whole.outcome == Understanding::Outcome::kMatch &&
                   (said_word_for_word || says_not(*whole.match)))) {
    Understanding no;
    no.words = std::move(whole.words);
    no.request = std::move(whole.request);
    no.ranking = std::move(whole.ranking);
    no.negated = true;
    no.reason = "a request not to do something, and no template of it says so";
    return no;
  }
  // Understood as a whole through a template word for word: done.
  const bool matched = whole.outcome == Understanding::Outcome::kMatch;
  if ((matched && said_word_for_word) || whole.words.size() < 4) return whole;
  // Every droppable lead-in is tried; the rest that fits its template best wins (word for
  // word is cost 0), the shortest lead-in on a tie.
  if (whole.words.size() > kMaxLeadInWords) return whole;
  const std::span<const std::string> words(whole.words);
  std::optional<Understanding> best;
  std::size_t best_at = 0;
  for (std::size_t at = 2; at + 2 <= words.size(); ++at) {
    if (!droppable_lead_in(words.first(at))) continue;
    Understanding rest = understand_whole(join_words(whole.words, at, words.size()), context);
    // Not understood as a whole: the rest must fit a template word for word. Taken by the
    // model as a whole: the rest only fills the same intent's slots without the lead-in, and
    // must fit one of its templates closely ("it's late, set an alarm for 7 tomorrow" is no
    // task "it is late set an alarm for").
    const bool word_for_word = rest.reason == kExactTemplate;
    if (rest.outcome != Understanding::Outcome::kMatch ||
        (!word_for_word && (!matched || rest.match->cost > 1.0F))) {
      continue;
    }
    if (word_for_word) rest.match->cost = 0;
    // A free-text slot fits nearly anything ("I need to find a good way to make soup"): the
    // model must also believe the rest is a request rather than out of scope.
    float p_intent = 0, p_none = 0;
    for (const RankedIntent& ranked : rest.ranking) {
      if (ranked.skill_id.empty()) p_none = ranked.probability;
      if (ranked.skill_id == rest.match->skill_id && ranked.intent == rest.match->intent) {
        p_intent = ranked.probability;
      }
    }
    if (p_intent <= p_none) continue;
    if (matched && (rest.match->skill_id != whole.match->skill_id ||
                    rest.match->intent != whole.match->intent)) {
      continue;
    }
    if (!best || rest.match->cost < best->match->cost) {
      best = std::move(rest);
      best_at = at;
    }
  }
  if (!best) return whole;
  best->reason = "a request after a lead-in (\"" + join_words(whole.words, 0, best_at) + "\")";
  best->words = whole.words;
  return *best;
}

Understanding Interpreter::understand_whole(std::string_view utterance,
                                            const Context& context) const {
  Understanding u;
  if (utterance.size() > kMaxUtteranceBytes) {
    u.reason = "too long (" + std::to_string(utterance.size()) + " bytes, at most " +
               std::to_string(kMaxUtteranceBytes) + ")";
    return u;
  }
  u.words = normalize(utterance);
  if (u.words.empty()) {
    u.reason = "no words";
    return u;
  }
  if (u.words.size() > kMaxUnderstoodWords) {
    u.reason = "too long (" + std::to_string(u.words.size()) + " words, at most " +
               std::to_string(kMaxUnderstoodWords) + ")";
    return u;
  }
  u.request = strip_politeness(u.words);
  const Impl& impl = *impl_;
  std::shared_ptr<const ModelState> state = impl.ensure_model();
  std::vector<float> p = state->model.probabilities(u.request);
  const float p_none = p[static_cast<std::size_t>(state->none_class)];
  // A dialogue answer ("you got it") is no request for a skill.
  float p_dialogue = 0;
  for (std::size_t k = static_cast<std::size_t>(state->none_class) + 1; k < p.size(); ++k) {
    p_dialogue = std::max(p_dialogue, p[k]);
  }

  // Intents best first by the model's belief; ties by registration order.
  std::vector<std::size_t> order(impl.intents.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return p[a] > p[b]; });

  // 1. A template that covers the words exactly (without the politeness, then as said).
  std::vector<std::string> spoken = u.words;
  if (spoken.size() >= 2 && (spoken[0] == "hey" || spoken[0] == "ok" || spoken[0] == "okay") &&
      spoken[1] == "marvin") {
    spoken.erase(spoken.begin(), spoken.begin() + 2);
  } else if (spoken.size() >= 2 && spoken[0] == "marvin") {
    spoken.erase(spoken.begin());
  }
  // The request first, so a text slot does not take the politeness ("... my glasses please").
  for (const auto* words : {&u.request, &spoken}) {
    auto exact = impl.exact_matches(*words, context);
    std::optional<std::size_t> best;
    for (std::size_t k = 0; k < exact.size(); ++k) {
      if (!exact[k]) continue;
      // Templates that fit equally well go to the intent the model prefers, not to the
      // first registered ("is there someone in the house": anyone_in's "is there someone in
      // {room}" against where_is's "is {what} in the house").
      if (!best || ranks_above(*exact[k], *exact[*best]) ||
          (!ranks_above(*exact[*best], *exact[k]) && p[k] > p[*best])) {
        best = k;
      }
    }
    if (!best) continue;
    // Another skill's template also fits word for word and the model clearly prefers it
    // ("remind me about the meeting": schedule, not medication).
    for (std::size_t k = 0; k < exact.size(); ++k) {
      if (exact[k] && impl.intents[k].spec.skill_id != impl.intents[*best].spec.skill_id &&
          p[k] > p[*best] + kModelOverridesExact) {
        best = k;
      }
    }
    Match m = impl.to_match(impl.intents[*best], std::move(exact[*best]->slots));
    m.literal_words = exact[*best]->literal_words;
    u.match = std::move(m);
    u.outcome = Understanding::Outcome::kMatch;
    u.reason = kExactTemplate;
    break;
  }

  // 1b. An example sentence of an intent without slots, said word for word (without the
  // politeness): the skill's author wrote it for that intent ("what's up" is a greeting,
  // though most "what is ..." requests are not). Intents with slots are left to the
  // templates, which fill them.
  if (u.outcome != Understanding::Outcome::kMatch) {
    auto example = state->slotless_examples.find(join_words(u.request));
    if (example != state->slotless_examples.end() &&
        example->second != ModelState::kSharedExample) {
      Match m = impl.to_match(impl.intents[example->second], {});
      m.confidence = p[example->second];
      u.match = std::move(m);
      u.outcome = Understanding::Outcome::kMatch;
      u.reason = kExactExample;
    }
  }

  // 2. The model's ranking, with tolerant template parses for the likeliest intents.
  std::vector<std::string> stems;
  std::vector<int> ids;
  for (const std::string& w : u.request) {
    stems.push_back(stem(w));
    ids.push_back(impl.vocabulary.find(w));
  }
  TolerantInput input{u.request, ids, stems};
  ContactBook contacts(context.contact_names);
  const TimeCue cue = time_cue(u.request);
  std::vector<std::optional<TolerantMatch>> parses(order.size());
  for (std::size_t r = 0; r < order.size() && r < kTolerantCandidates; ++r) {
    const CompiledIntent& intent = impl.intents[order[r]];
    IntentSlotReader reader(intent, context, contacts, cue);
    for (const CompiledTemplate& compiled : intent.templates) {
      auto m =
          match_tolerant(compiled, input, state->word_stems, state->synonyms[order[r]], reader);
      if (m && (!parses[r] || m->cost < parses[r]->cost ||
                (m->cost == parses[r]->cost && m->literal_words > parses[r]->literal_words))) {
        parses[r] = std::move(m);
      }
    }
  }
  for (std::size_t r = 0; r < order.size() && u.ranking.size() < 4; ++r) {
    const CompiledIntent& intent = impl.intents[order[r]];
    u.ranking.push_back({intent.spec.skill_id, intent.spec.intent, p[order[r]],
                         parses[r] ? parses[r]->cost : -1.0F});
  }
  RankedIntent none{"", "none", p_none, -1};
  auto at = std::find_if(u.ranking.begin(), u.ranking.end(),
                         [&](const RankedIntent& r) { return r.probability < p_none; });
  u.ranking.insert(at, none);
  if (u.outcome == Understanding::Outcome::kMatch) {
    // A word-for-word match through a free-text slot can be the wrong skill ("remind me
    // about the meeting" fits medication's "remind me about {medicine}"): another skill's
    // intent the model is sure of, and whose template fits closely, wins.
    const CompiledIntent& top = impl.intents[order.front()];
    const auto chosen = std::find_if(order.begin(), order.end(), [&](std::size_t k) {
      return impl.intents[k].spec.skill_id == u.match->skill_id &&
             impl.intents[k].spec.intent == u.match->intent;
    });
    if (top.spec.skill_id != u.match->skill_id && parses[0] &&
        parses[0]->cost <= kLowTemplateCost && p[order.front()] >= kAcceptProbability &&
        chosen != order.end() && p[order.front()] > p[*chosen] + kModelOverridesExact) {
      Match m = impl.to_match(top, parses[0]->slots);
      m.confidence = p[order.front()];
      m.cost = parses[0]->cost;
      m.literal_words = parses[0]->literal_words;
      u.match = std::move(m);
      u.reason = "the model prefers another skill's close template";
    }
    return u;
  }
  if (order.empty()) {
    u.reason = "no intents";
    return u;
  }

  auto reading = [&](std::size_t r) {
    const CompiledIntent& intent = impl.intents[order[r]];
    Match m = parses[r] ? impl.to_match(intent, parses[r]->slots) : impl.to_match(intent, {});
    m.confidence = p[order[r]];
    m.cost = parses[r] ? parses[r]->cost : TolerantCosts::kMaxCost;
    m.literal_words = parses[r] ? parses[r]->literal_words : 0;
    return m;
  };
  const float p1 = p[order[0]];
  // An intent all of whose templates name a person or thing (find {what}, tell {name} ...)
  // acts only on a request that names one: a tolerant parse must fill such a slot with words
  // that look like one (slot_plausibility.h). "find a recipe for hamburgers" is sure to be
  // a finding request to the model, but names nothing that could be in a home.
  if (impl.needs_entity(order[0]) && !impl.fills_entity(order[0], parses[0])) {
    u.reason = "names no person or thing for " + impl.intents[order[0]].spec.intent;
    return u;
  }
  // When its template fits only loosely, the model's belief rests on the intent's examples,
  // which teach its verbs ("find", "where is", "guide me") but not what fills the slot: the
  // looser the fit, the surer the slot must name someone or something. A loose fit needs a
  // contact or a word that names one without the benefit of the doubt ("find a recipe for
  // hamburgers" -> "recipe"); a very loose one needs a contact ("where does cannabis
  // originate from" fits "where is {what}" only by dropping three words).
  if (impl.needs_entity(order[0]) && parses[0]->cost > kLooseEntityTemplateCost &&
      !impl.fills_entity_strictly(order[0], *parses[0], contacts,
                                  parses[0]->cost > kVeryLooseEntityTemplateCost)) {
    u.reason = "names no person or thing for sure for " + impl.intents[order[0]].spec.intent;
    return u;
  }
  if (p_dialogue > p1) {
    u.reason = "a dialogue answer, not a request";
    return u;
  }
  const float p2 = order.size() > 1 ? p[order[1]] : 0.0F;
  // A forgiving parse must rest on at least two of the template's own words: one function
  // word plus a free-text slot ("is {device} on" for "is flu contagious") fits almost anything.
  const bool low_cost = parses[0] && parses[0]->cost <= kLowTemplateCost &&
                        (parses[0]->cost == 0 || parses[0]->literal_words >= 2);
  const bool close_call = p2 >= kAskEach && p2 >= kCloseCall * p1 && !low_cost;
  const bool template_only = impl.intents[order[0]].spec.examples.empty();
  const float none_ratio_with_template =
      template_only ? kNoneRatioTemplateOnly : kNoneRatioWithTemplate;
  const float accept_with_template = template_only ? kAcceptTemplateOnly : kAcceptWithTemplate;
  if (!close_call &&
      ((p1 > p_none * kNoneRatio && p1 >= kAcceptProbability) ||
       (low_cost && p1 >= accept_with_template && p1 >= p_none * none_ratio_with_template))) {
    u.match = reading(0);
    u.outcome = Understanding::Outcome::kMatch;
    u.reason = p1 >= kAcceptProbability ? "the model is sure" : "close template and model agree";
    return u;
  }
  if (p2 >= kAskEach && p1 + p2 >= kAskTogether && p1 + p2 > p_none * kNoneRatio) {
    u.choices = {reading(0), reading(1)};
    u.outcome = Understanding::Outcome::kAsk;
    u.reason =
        close_call ? "the two likeliest intents are too close to choose" : "two intents are close";
    return u;
  }
  // The top intent's skill as a whole: its intents' belief added up.
  float p_skill = 0;
  std::size_t second_of_skill = 0;  // rank of the skill's next intent (0 = none)
  for (std::size_t r = 0; r < order.size(); ++r) {
    // Only intents the model gives real weight: a skill with many intents would otherwise
    // add up to a lot of small doubts.
    if (impl.intents[order[r]].spec.skill_id != impl.intents[order[0]].spec.skill_id ||
        p[order[r]] < kSkillShare) {
      continue;
    }
    p_skill += p[order[r]];
    if (r > 0 && second_of_skill == 0) second_of_skill = r;
  }
  if (p_skill >= kSkillProbability && p_skill > p_none * kNoneRatio) {
    if (second_of_skill == 1 && p2 >= kCloseCall * p1 * 0.5F) {
      u.choices = {reading(0), reading(1)};
      u.outcome = Understanding::Outcome::kAsk;
      u.reason = "the skill is clear, not which of its intents";
      return u;
    }
    u.match = reading(0);
    u.outcome = Understanding::Outcome::kMatch;
    u.reason = "the skill is clear and this is its likeliest intent";
    return u;
  }
  u.reason = p_none >= p1 ? "out of scope is likeliest" : "not sure enough";
  return u;
}

}  // namespace marvin::interpret
