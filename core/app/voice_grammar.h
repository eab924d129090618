// What the recognizer may hear in the host: the command grammar generated from the loaded
// skills' templates and today's slot values, and the grammar for the answer to a question.
//
// Two halves, because they live on different threads: SkillPhrases is copied from the
// registry on the thread that may read it (skills/registry.h, Threading: the host loop's,
// between utterances, or before it runs); SlotValues are read from personal data (thread-
// safe) by the voice thread. The grammars are then built from both, on the voice thread.
//
// Slot types become grammar slots: contact -> the contacts' names, aliases and first names;
// list -> its values; number, duration, datetime -> the built-in rules; text -> the phrases
// known now (see "Text slots").
//
// Text slots. Free text (command_grammar.h's word loop) does not work with pocketsphinx's
// en-us model on espeak-ng speech, measured: in "remind me to {task}" the loop of ~230
// everyday words always finds a word string that fits the sound better than the words said
// ("remind me to take my pills" -> "remind me to do you go my to you you old off"), and a
// loop after a short shared prefix ("what's {name} number") costs the other sentences their
// confidence ("what time is it": +5.6 alone, "no sentence fits" next to it). So a text slot
// is heard as one of the phrases known now: the titles of stored reminders, contact names,
// and everyday_tasks(). "remind me to water the orchids" is heard only once such a reminder
// exists (typed, or added by a carer); the limit is stated in the README.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "data/personal_data.h"
#include "navigation/going_places.h"
#include "perception/command_grammar.h"
#include "skills/manifest.h"
#include "skills/registry.h"

namespace marvin::app {

struct SkillPhrases {
  struct Intent {
    std::string name;  // "schedule.remind"
    std::vector<std::string> templates;
    std::vector<skills::SlotDecl> slots;
  };
  struct Question {
    std::string text;         // a slot's question, or a confirmation with {slot} holes
    skills::SlotDecl slot;    // the slot asked for (confirmations: unused)
    bool yes_no = false;      // a confirmation: the answer is yes or no
  };
  std::vector<Intent> intents;
  std::vector<Question> questions;

  bool operator==(const SkillPhrases&) const;
};

// Copies the phrases of every loaded skill. Only on a thread that may read the registry.
SkillPhrases skill_phrases(const skills::Registry& registry);

struct SlotValues {
  std::vector<std::string> contacts;   // names, aliases and first names
  // Text slots: stored reminder titles, contact names and aliases, everyday_tasks().
  std::vector<std::string> text_phrases;
  bool operator==(const SlotValues&) const = default;
};

// Things people ask to be reminded of ("take my pills", "water the plants", ...).
const std::vector<std::string>& everyday_tasks();

// Reads contacts and reminders now; empty (and logged) when personal data is unavailable.
SlotValues current_slot_values(data::PersonalData& data);

// Adds the rooms, places and people the robot can go to ("the kitchen", "kitchen", "Anna"),
// so "go to the kitchen" is heard; no-op without a map (`places` null).
void add_place_names(navigation::GoingPlaces* places, SlotValues& values);

using KnownWord = std::function<bool(std::string_view)>;

// The command grammar (JSGF). Throws perception::GrammarError when nothing can be heard.
// Every sentence may start with `wake_word` (GrammarOptions::optional_prefix).
perception::GrammarResult command_grammar(const SkillPhrases& phrases, const SlotValues& values,
                                          const KnownWord& known,
                                          const std::string& wake_word = "marvin");

// The grammar for the answer to `question` (as said, e.g. "Sorry, I didn't get that. When
// should I remind you?"): the slot's values (with "it's", "to", "for" before them) for a
// slot question, yes/no for a confirmation, the conversation phrases always. "" when the
// question is not one the manifests ask (a skill's own question): keep the command grammar.
std::string answer_grammar(const SkillPhrases& phrases, const SlotValues& values,
                           std::string_view question, const KnownWord& known,
                           const std::string& wake_word = "marvin");

}  // namespace marvin::app
