// The semantic interpreter, first version: utterance text -> skill intent + typed slots.
//
// Skills declare intents with utterance templates in the style of Home Assistant's hassil /
// Rhasspy:
//
//   "remind me to {task} (at|on) {when}"      slots: task (text), when (datetime)
//   "set [a] timer for {duration}"            slots: duration (duration)
//   "(turn|switch) on [the] {device}"         slots: device (list: lamp, fan, radio)
//
// Template syntax: words; `(a|b|c)` alternatives (each may hold several words, optionals,
// nested groups); `[a]` optional words (`[a|b]` = optional alternatives); `{name}` a slot,
// declared in IntentSpec::slots. Templates are normalised like utterances (lower case,
// punctuation dropped, number words as digits), so "Set a timer" and "set a timer" are the
// same template.
//
// Matching: an utterance matches a template only if the WHOLE utterance is consumed by it.
// "No match" (std::nullopt) is a normal result, never a guess. When several templates
// match, the winner is the one with the most literal (non-slot) words matched; ties go to
// the more typed match (fewer text-slot words), then to the intent registered first, then to
// the template listed first. Same inputs, same answer, always.
//
// Slot types and what SlotValue::value holds:
//   kNumber   -> JSON number (integer when whole): "twenty five" -> 25, "2.5" -> 2.5
//   kDuration -> seconds (integer): "20 minutes" -> 1200, "an hour and a half" -> 5400
//   kDateTime -> {"at":"YYYY-MM-DDTHH:MM" (local wall time in Context::time_zone),
//                 "utc_ms":N (the same instant), "time_zone":"Europe/Berlin",
//                 "time_given":bool (false: no time of day said, 09:00 assumed),
//                 "day_given":bool (false: only a time of day said, "at 3 pm"),
//                 "recurrence":{"kind":"once|daily|weekdays|weekly|interval", ...}}
//                 daily: "time":"HH:MM"; weekdays/weekly: "weekdays":["monday",...] and
//                 "time"; interval: "every_seconds":N.
//                 "at" is the FIRST occurrence strictly after Context::now_utc_ms.
//                 Grammar and resolution rules: time_expression.h, time_resolution.h.
//   kContact  -> the contact name as spelled in Context::contact_names
//   kList     -> the list item as spelled in SlotSpec::values
//   kText     -> the words as heard (normalised), 1..8 words
//
// Thread safety: add() and remove_skill() must not run concurrently with anything else; the
// const members may be called from any number of threads at once.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

namespace marvin::interpret {

enum class SlotType { kNumber, kDuration, kDateTime, kContact, kList, kText };

// "number", "duration", "datetime", "contact", "list", "text".
const char* to_string(SlotType type);
// The inverse of to_string(SlotType); nullopt for an unknown name.
std::optional<SlotType> slot_type_from_string(std::string_view name);

struct SlotSpec {
  std::string name;
  SlotType type = SlotType::kText;
  std::vector<std::string> values;  // kList items (may hold several words: "living room")
};

struct IntentSpec {
  std::string skill_id;
  std::string intent;
  std::vector<std::string> templates;
  std::vector<SlotSpec> slots;
  // Natural sentences people say for this intent (not templates: no syntax), used to train
  // the intent model. Optional.
  std::vector<std::string> examples{};
  // Words people use for a template word: {"reminder", {"alarm", "alert"}}. Used by the
  // tolerant matcher (single words) and to vary the model's training sentences. Optional.
  std::vector<std::pair<std::string, std::vector<std::string>>> synonyms{};
};

struct SlotValue {
  std::string text;      // words as heard (normalised)
  nlohmann::json value;  // normalised value, see the table at the top of this file
};

struct Match {
  std::string skill_id;
  std::string intent;
  std::map<std::string, SlotValue> slots;  // only the slots the utterance filled
  int literal_words = 0;                   // template words matched literally (the rank)
  float confidence = 1.0F;  // 1 for a word-for-word template match, else the model's belief
  float cost = 0.0F;        // tolerant-matching cost of the slots' parse (0 = exact)
};

// One intent and how much the model believes in it (skill_id "" = out of scope).
struct RankedIntent {
  std::string skill_id;
  std::string intent;
  float probability = 0;
  float cost = -1;  // best tolerant template cost, -1 when not tried or no parse
};

// What the interpreter made of an utterance (understand()).
struct Understanding {
  enum class Outcome { kMatch, kAsk, kNone };
  Outcome outcome = Outcome::kNone;
  std::vector<std::string> words;    // normalised
  std::vector<std::string> request;  // without wake word, politeness and filler
  std::vector<RankedIntent> ranking;  // best first, at most 5
  std::optional<Match> match;         // kMatch: the request
  std::vector<Match> choices;         // kAsk: the two likeliest readings, best first
  std::string reason;                 // why, in a few words ("exact template", ...)
  // kNone for a request not to do something ("don't turn off the lights", "never call
  // Sam"): the model knows the verbs, not the "not", so only a template that says the
  // negation itself ("don't answer it") acts on one. The manager answers "OK, I won't."
  bool negated = false;
};

// What the interpreter needs to know about the world to resolve slots.
struct Context {
  std::int64_t now_utc_ms = 0;             // "now", milliseconds since the Unix epoch (UTC)
  std::string time_zone = "UTC";           // IANA name, e.g. "Europe/Berlin"
  std::vector<std::string> contact_names;  // for kContact slots; "my daughter" for a relation
};

// Conversation intents every utterance is checked against first (the manager decides what
// they mean in the current dialogue; stop always wins).
enum class Builtin { kNone, kStop, kYes, kNo, kRepeat };

// A template that does not parse. what() names skill, intent, template and 1-based column.
class TemplateError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class Interpreter {
 public:
  Interpreter();
  ~Interpreter();
  Interpreter(const Interpreter& other);
  Interpreter& operator=(const Interpreter& other);
  Interpreter(Interpreter&& other) noexcept;
  Interpreter& operator=(Interpreter&& other) noexcept;

  // Registers an intent and compiles its templates. Throws TemplateError (a
  // std::runtime_error) naming skill, intent, template and position on a bad template, an
  // undeclared or duplicate slot, or an empty skill_id/intent; on error nothing is added.
  void add(const IntentSpec& spec);

  // Unregisters every intent of `skill_id` (a skill being unloaded or replaced by another
  // version); returns how many were removed. Words only it used stay in the vocabulary
  // (harmless: no template refers to them). Same thread rule as add().
  std::size_t remove_skill(std::string_view skill_id);

  // Number of intents added so far (and not removed).
  std::size_t size() const;

  // Sentences claimed by two different skills, one line each, e.g.
  //   `"turn on the lamp" is claimed by skill "lights" (intent on) and skill "power"
  //    (intent switch_on)`, plus "(and N more sentences)" when a pair shares several.
  //    Checked on the sentences each template can produce: list slots (up to 32 values) as
  //    their values, other slots as a placeholder of their type ("{text}", "{duration}"), so
  //    two slots of the same type count as the same words. Intents of one skill never
  //    conflict with each other (ranking orders them).
  std::vector<std::string> conflicts() const;

  // stop/cancel ("stop", "cancel", "marvin stop", "never mind", ...), yes/no ("yes",
  // "yeah", "sure", "no", "nope", ...), repeat ("repeat", "say that again", ...). The whole
  // utterance must be the phrase (a leading "marvin" and "please" are allowed).
  Builtin builtin(std::string_view utterance) const;

  // The best match of the whole utterance against every registered template, or nullopt.
  // A leading wake word ("marvin", "hey marvin", "ok marvin") is ignored; if nothing
  // matches, a leading or trailing "please" is dropped and matching tried once more.
  // Throws std::runtime_error naming the zone if a datetime slot is tried and
  // Context::time_zone is not a known IANA zone.
  std::optional<Match> match(std::string_view utterance, const Context& context) const;

  // Word-for-word only: the best template that covers the whole utterance (after the wake
  // word; a leading or trailing "please" dropped if nothing matches), or nullopt. This is
  // understand()'s first step; skills' tests use it to check their templates.
  std::optional<Match> match_exact(std::string_view utterance, const Context& context) const;

  // The full decision behind match(): normalisation, politeness stripped, an exact template
  // match if any; else the intent model's ranking (trained from every intent's expanded
  // templates and examples, plus out-of-scope sentences) combined with tolerant template
  // matching (tolerant_matcher.h) for the slots. Accepted when the model is sure enough
  // (kAcceptProbability) and out of scope is not likelier; kAsk when the top two intents
  // are close and together likely; else kNone. An utterance with no words, more than 64
  // words or more than 4096 bytes is kNone. Deterministic: the same intents give the same
  // model and answers. An utterance not understood as a whole (or only by the model) may be
  // a request after a lead-in ("I'm going to bed, turn off all the lights"): the lead-in
  // whose rest fits a template best is dropped, unless it negates, asks, makes the rest a
  // condition or reports someone else's words ("if", "don't", "how do I", "ask Anna to").
  // A request that starts with "don't" or "never" is only acted on through a template that
  // says it word for word, or by an intent with a template that negates the same verb
  // (Understanding::negated).
  Understanding understand(std::string_view utterance, const Context& context) const;

  // Builds the intent model now (it is otherwise built by the first understand()/match()
  // after add()/remove_skill()). Returns the model's size in bytes.
  std::size_t build_model() const;

  // Parses a dialogue answer as one value of `slot` ("at eight" for a datetime, "Anna" for
  // a contact). Up to two leading fillers ("it's", "to", "for", "the", ...) and a trailing
  // "please" are tolerated; a text answer may hold up to 24 words. `request` is what the
  // answer completes: "6" answering for "set an alarm" is 6 am, as in "set an alarm for 6".
  // nullopt when the answer is not a value of that type. Throws like match() on an unknown
  // time zone.
  std::optional<SlotValue> parse_slot(const SlotSpec& slot, std::string_view answer,
                                      const Context& context, std::string_view request = {}) const;

 private:
  Understanding understand_whole(std::string_view utterance, const Context& context) const;

  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace marvin::interpret
