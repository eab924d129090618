#include "interpret/interpreter.h"

#include <algorithm>
#include <array>
#include <set>

#include "interpret/builtins.h"
#include "interpret/intent_table.h"
#include "interpret/matcher.h"
#include "interpret/normalizer.h"
#include "interpret/slot_parsers.h"
#include "interpret/template.h"

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

// Words a dialogue answer may start with before the value: "it's eight", "to Anna".
constexpr std::array<std::string_view, 9> kAnswerFillers{
    "it's", "it", "is", "its", "to", "for", "the", "about", "call"};

// A dialogue answer may say more than an utterance's text slot.
constexpr std::size_t kAnswerTextMaxWords = 24;

class IntentSlotReader final : public SlotReader {
 public:
  IntentSlotReader(const CompiledIntent& intent, const Context& context,
                   const ContactBook& contacts)
      : intent_(intent), context_(context), contacts_(contacts) {}

  std::optional<SlotValue> read(int slot, std::span<const std::string> words) const override {
    return read_slot_value(intent_.slots[static_cast<std::size_t>(slot)], words, context_,
                           contacts_, kTextSlotMaxWords);
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
};

std::string template_error(const IntentSpec& spec, std::string_view text,
                           std::size_t column, const std::string& message) {
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

struct Interpreter::Impl {
  Vocabulary vocabulary;
  std::vector<CompiledIntent> intents;

  std::optional<Match> best_match(const std::vector<std::string>& words,
                                  const Context& context) const;
};

Interpreter::Interpreter() : impl_(std::make_unique<Impl>()) {}
Interpreter::~Interpreter() = default;
Interpreter::Interpreter(const Interpreter& other)
    : impl_(std::make_unique<Impl>(*other.impl_)) {}
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
          throw TemplateError(intent_error(spec, "list slot \"" + slot.name +
                                                     "\" has a value without words: \"" +
                                                     value + "\""));
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
}

std::size_t Interpreter::remove_skill(std::string_view skill_id) {
  auto& intents = impl_->intents;
  std::size_t before = intents.size();
  std::erase_if(intents, [&](const CompiledIntent& i) { return i.spec.skill_id == skill_id; });
  return before - intents.size();
}

std::size_t Interpreter::size() const { return impl_->intents.size(); }

std::vector<std::string> Interpreter::conflicts() const {
  return find_conflicts(impl_->intents, impl_->vocabulary);
}

Builtin Interpreter::builtin(std::string_view utterance) const {
  return classify_builtin(utterance);
}

std::optional<Match> Interpreter::Impl::best_match(const std::vector<std::string>& words,
                                                   const Context& context) const {
  if (words.empty()) return std::nullopt;
  std::vector<int> ids(words.size());
  std::vector<char> present(vocabulary.size(), 0);
  for (std::size_t i = 0; i < words.size(); ++i) {
    ids[i] = vocabulary.find(words[i]);
    if (ids[i] != Vocabulary::kUnknown) present[static_cast<std::size_t>(ids[i])] = 1;
  }
  ContactBook contacts(context.contact_names);

  std::optional<TemplateMatch> best;
  const CompiledIntent* best_intent = nullptr;
  for (const CompiledIntent& intent : intents) {
    IntentSlotReader reader(intent, context, contacts);
    for (const CompiledTemplate& compiled : intent.templates) {
      if (words.size() < compiled.min_words || words.size() > compiled.max_words) continue;
      // A template that cannot beat the best so far is not tried.
      if (best && compiled.literal_words_max < best->literal_words) continue;
      bool has_all = std::all_of(
          compiled.required_words.begin(), compiled.required_words.end(),
          [&](int id) { return present[static_cast<std::size_t>(id)] != 0; });
      if (!has_all) continue;
      auto found = match_template(compiled, words, ids, reader);
      if (found && (!best || ranks_above(*found, *best))) {
        best = std::move(found);
        best_intent = &intent;
      }
    }
  }
  if (!best) return std::nullopt;
  Match match;
  match.skill_id = best_intent->spec.skill_id;
  match.intent = best_intent->spec.intent;
  match.literal_words = best->literal_words;
  for (SlotCapture& capture : best->slots) {
    match.slots[best_intent->slots[static_cast<std::size_t>(capture.slot)].spec.name] =
        std::move(capture.value);
  }
  return match;
}

std::optional<Match> Interpreter::match(std::string_view utterance,
                                        const Context& context) const {
  std::vector<std::string> words = normalize(utterance);
  // The wake word is never content: "Marvin, what time is it".
  std::size_t skip = 0;
  if (words.size() >= 2 && (words[0] == "hey" || words[0] == "ok" || words[0] == "okay") &&
      words[1] == "marvin") {
    skip = 2;
  } else if (!words.empty() && words[0] == "marvin") {
    skip = 1;
  }
  words.erase(words.begin(), words.begin() + static_cast<std::ptrdiff_t>(skip));
  if (auto found = impl_->best_match(words, context)) return found;
  // Politeness the templates did not foresee: "please turn on the lamp", "... please".
  bool changed = false;
  if (words.size() >= 2 && words.front() == "please") {
    words.erase(words.begin());
    changed = true;
  }
  if (words.size() >= 2 && words.back() == "please") {
    words.pop_back();
    changed = true;
  }
  if (changed) return impl_->best_match(words, context);
  return std::nullopt;
}

std::optional<SlotValue> Interpreter::parse_slot(const SlotSpec& slot, std::string_view answer,
                                                 const Context& context) const {
  PreparedSlot prepared = prepare_slot(slot);
  ContactBook contacts(context.contact_names);
  std::vector<std::string> words = normalize(answer);
  if (words.size() >= 2 && words.back() == "please") words.pop_back();
  std::size_t begin = 0;
  // Try the answer as given, then without up to two leading fillers ("it's", "to", ...).
  for (int attempt = 0; attempt < 3 && begin < words.size(); ++attempt) {
    std::span<const std::string> span(words.data() + begin, words.size() - begin);
    if (auto value = read_slot_value(prepared, span, context, contacts, kAnswerTextMaxWords)) {
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

}  // namespace marvin::interpret
