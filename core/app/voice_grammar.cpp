#include "app/voice_grammar.h"

#include <algorithm>

#include "common/log.h"

namespace marvin::app {
namespace {

namespace perception = marvin::perception;

perception::GrammarSlot grammar_slot(const skills::SlotDecl& slot, const SlotValues& values) {
  perception::GrammarSlot g;
  g.name = slot.name;
  switch (slot.kind) {
    case skills::SlotKind::kNumber: g.kind = perception::SlotKind::kNumber; break;
    case skills::SlotKind::kDuration: g.kind = perception::SlotKind::kDuration; break;
    case skills::SlotKind::kDateTime: g.kind = perception::SlotKind::kDateTime; break;
    case skills::SlotKind::kText:  // see "Text slots" in voice_grammar.h
      g.kind = perception::SlotKind::kPhrases;
      g.phrases = values.text_phrases;
      break;
    case skills::SlotKind::kContact:
      g.kind = perception::SlotKind::kPhrases;
      g.phrases = values.contacts;
      break;
    case skills::SlotKind::kList:
      g.kind = perception::SlotKind::kPhrases;
      g.phrases = slot.values;
      break;
  }
  return g;
}

perception::GrammarOptions grammar_options(const std::string& wake_word) {
  perception::GrammarOptions options;
  options.optional_prefix = wake_word;
  // People speak to the robot as they type to it: "could you please ..." (issue 16).
  options.polite_before = perception::GrammarOptions::default_polite_before();
  options.polite_after = perception::GrammarOptions::default_polite_after();
  return options;
}

// "Shall I call {contact}?" matches "Shall I call Anna Schmidt?": the literal pieces in
// order, anything in the holes.
bool matches_with_holes(std::string_view pattern, std::string_view text) {
  std::size_t at = 0;
  bool first = true;
  while (!pattern.empty()) {
    const std::size_t open = pattern.find('{');
    const std::string_view piece = pattern.substr(0, open);
    if (!piece.empty()) {
      const std::size_t found = text.find(piece, at);
      if (found == std::string_view::npos || (first && found != 0)) return false;
      at = found + piece.size();
    }
    first = false;
    if (open == std::string_view::npos) return at == text.size();
    const std::size_t close = pattern.find('}', open);
    if (close == std::string_view::npos) return false;
    pattern = pattern.substr(close + 1);
    if (pattern.empty()) return true;  // a hole at the end takes the rest
  }
  return at == text.size();
}

bool ends_with(std::string_view text, std::string_view tail) {
  return text.size() >= tail.size() && text.substr(text.size() - tail.size()) == tail;
}

}  // namespace

bool SkillPhrases::operator==(const SkillPhrases& other) const {
  auto key = [](const SkillPhrases& p) {
    std::string k;
    for (const Intent& i : p.intents) {
      k += i.name + '\n';
      for (const std::string& t : i.templates) k += t + '\n';
      for (const skills::SlotDecl& s : i.slots) {
        k += s.name + ':' + skills::to_string(s.kind) + '\n';
        for (const std::string& v : s.values) k += v + '\n';
      }
    }
    for (const Question& q : p.questions) k += q.text + '\n';
    return k;
  };
  return key(*this) == key(other);
}

SkillPhrases skill_phrases(const skills::Registry& registry) {
  SkillPhrases phrases;
  for (const auto& skill : registry.skills()) {
    for (const skills::IntentDecl& intent : skill->manifest.intents) {
      phrases.intents.push_back({skill->manifest.id + "." + intent.name, intent.templates,
                                 intent.slots});
      for (const skills::SlotDecl& slot : intent.slots) {
        if (!slot.question.empty()) phrases.questions.push_back({slot.question, slot, false});
      }
      if (intent.confirm) phrases.questions.push_back({intent.confirm_question, {}, true});
    }
  }
  return phrases;
}

const std::vector<std::string>& everyday_tasks() {
  // What people ask to be reminded of most (errands, medicine, meals, calls, the house);
  // carers extend it by adding reminders, whose titles are heard from then on.
  static const std::vector<std::string> tasks = {
      "take my pills", "take my medicine", "take my tablets", "take my insulin",
      "take my vitamins", "check my blood pressure", "check my blood sugar", "drink some water",
      "drink water", "eat lunch", "eat dinner", "have breakfast", "have lunch", "have dinner",
      "make tea", "call my daughter", "call my son", "call my sister", "call my brother",
      "call the doctor", "call the pharmacy", "water the plants", "water the flowers",
      "feed the cat", "feed the dog", "walk the dog", "take out the bins", "take out the rubbish",
      "do the laundry", "do the dishes", "do my exercises", "go to the doctor",
      "go to the dentist", "go shopping", "buy bread", "buy milk", "pay the rent",
      "pay the bills", "close the windows", "turn off the oven", "turn off the stove",
      "lock the door", "charge my phone", "watch the news", "go to bed", "take a nap",
      "take a shower", "brush my teeth", "visit my friend", "pick up my glasses"};
  return tasks;
}

void add_place_names(navigation::GoingPlaces* places, SlotValues& values) {
  if (!places) return;
  for (const std::string& name : places->place_names()) values.text_phrases.push_back(name);
}

SlotValues current_slot_values(data::PersonalData& data) {
  SlotValues values;
  try {
    for (const data::Contact& contact : data.list_contacts()) {
      values.contacts.push_back(contact.name);
      for (const std::string& alias : contact.aliases) values.contacts.push_back(alias);
      // The interpreter resolves a unique first name ("call anna" -> "Anna Schmidt").
      const std::vector<std::string> words = perception::grammar_words(contact.name);
      if (words.size() > 1) values.contacts.push_back(words.front());
      values.text_phrases.push_back(contact.name);
      for (const std::string& alias : contact.aliases) values.text_phrases.push_back(alias);
    }
    for (const data::Reminder& reminder : data.list_reminders()) {
      values.text_phrases.push_back(reminder.title);
    }
  } catch (const std::exception& e) {
    log(LogLevel::kWarning, "voice", std::string("slot values unavailable: ") + e.what());
  }
  for (const std::string& task : everyday_tasks()) values.text_phrases.push_back(task);
  return values;
}

perception::GrammarResult command_grammar(const SkillPhrases& phrases, const SlotValues& values,
                                          const KnownWord& known, const std::string& wake_word) {
  std::vector<perception::GrammarIntent> intents;
  for (const SkillPhrases::Intent& intent : phrases.intents) {
    perception::GrammarIntent g{intent.name, intent.templates, {}};
    for (const skills::SlotDecl& slot : intent.slots) g.slots.push_back(grammar_slot(slot, values));
    intents.push_back(std::move(g));
  }
  return perception::build_command_grammar(intents, grammar_options(wake_word), known);
}

std::string answer_grammar(const SkillPhrases& phrases, const SlotValues& values,
                           std::string_view question, const KnownWord& known,
                           const std::string& wake_word) {
  const perception::GrammarOptions options = grammar_options(wake_word);
  for (const SkillPhrases::Question& q : phrases.questions) {
    // The manager asks again with "Sorry, I didn't get that. " or "Please answer yes or
    // no. " in front.
    const bool asked = q.yes_no ? matches_with_holes(q.text, question) ||
                                      (question.find(". ") != std::string_view::npos &&
                                       matches_with_holes(q.text, question.substr(question.find(". ") + 2)))
                                : ends_with(question, q.text);
    if (!asked) continue;
    std::vector<perception::GrammarIntent> intents;
    if (!q.yes_no) {
      intents.push_back({"answer." + q.slot.name, {"[it's|it is|to|for] {" + q.slot.name + "}"},
                         {grammar_slot(q.slot, values)}});
    }
    try {
      return perception::build_command_grammar(intents, options, known).jsgf;
    } catch (const perception::GrammarError& e) {
      log(LogLevel::kWarning, "voice", std::string("no answer grammar: ") + e.what());
      return "";
    }
  }
  return "";
}

}  // namespace marvin::app
