// Understanding requests as people say them: politeness, tolerant matching with costs, the
// intent model (same skills, same model) and its out-of-scope threshold, bad input.
#include <doctest/doctest.h>

#include <chrono>
#include <string>
#include <vector>

#include "interpret/interpreter.h"
#include "interpret/normalizer.h"
#include "interpret/phrasing.h"
#include "interpret/tolerant_matcher.h"

using marvin::interpret::Builtin;
using marvin::interpret::Context;
using marvin::interpret::Interpreter;
using marvin::interpret::SlotType;
using marvin::interpret::Understanding;
namespace mi = marvin::interpret;

namespace {

using Words = std::vector<std::string>;

Context fixed_context() {
  Context context;
  context.now_utc_ms = 1795600000000;  // 2026-11-25T07:06:40Z
  context.time_zone = "Europe/Berlin";
  return context;
}

// A small home: time, reminders, a timer, each with a few examples as a skill would write.
Interpreter small_home() {
  Interpreter in;
  mi::IntentSpec time{"clock", "time", {"what time is it", "what is the time"}, {}};
  time.examples = {"tell me the time", "what's the time right now", "do you have the time",
                   "how late is it", "current time please"};
  in.add(time);
  mi::IntentSpec remind{"reminders",
                        "add",
                        {"remind me to {task} {when}", "set [a] reminder to {task} {when}"},
                        {{"task", SlotType::kText, {}}, {"when", SlotType::kDateTime, {}}}};
  remind.examples = {"remind me to call mum tonight", "set an alarm for 7",
                     "i need a reminder for the dentist", "wake me up at 6",
                     "don't let me forget the bins on monday"};
  remind.synonyms = {{"reminder", {"alarm", "alert"}}};
  in.add(remind);
  mi::IntentSpec timer{"timer",
                       "set",
                       {"(set|start) [a] timer for {duration}"},
                       {{"duration", SlotType::kDuration, {}}}};
  timer.examples = {"start a 5 minute timer", "timer for ten minutes", "count down 3 minutes",
                    "i need a timer", "set the kitchen timer"};
  in.add(timer);
  return in;
}

class TextReader final : public mi::SlotReader {
 public:
  std::optional<mi::SlotValue> read(int, std::span<const std::string> words) const override {
    return mi::SlotValue{mi::join_words(Words(words.begin(), words.end()), 0, words.size()),
                         nullptr};
  }
  bool is_text(int) const override { return true; }
  std::size_t max_words(int) const override { return 8; }
};

// The cost of reading `utterance` with `text`'s template, or -1 when it does not parse.
float tolerant_cost(const char* text, const char* utterance,
                    const mi::SynonymTable& synonyms = {}) {
  mi::Vocabulary vocabulary;
  mi::CompiledTemplate compiled;
  mi::TemplateSyntaxError error;
  REQUIRE(mi::compile_template(text, {"thing"}, {8}, vocabulary, compiled, error));
  std::vector<std::string> stems_by_id(vocabulary.size());
  vocabulary.for_each([&](const std::string& w, int id) {
    stems_by_id[static_cast<std::size_t>(id)] = mi::stem(w);
  });
  Words words = mi::normalize(utterance);
  std::vector<int> ids;
  Words stems;
  for (const auto& w : words) {
    ids.push_back(vocabulary.find(w));
    stems.push_back(mi::stem(w));
  }
  mi::SynonymTable table;
  for (const auto& [said, written] : synonyms) {
    for (int id : written) table[said].push_back(id);
  }
  (void)table;
  auto m = mi::match_tolerant(compiled, {words, ids, stems}, stems_by_id, synonyms,
                              TextReader());
  return m ? m->cost : -1.0F;
}

}  // namespace

TEST_CASE("tolerant matching: a slot never takes a template word counted as missing") {
  // "help me find my slippers" with `find {thing}`: "find" missing and the whole sentence in
  // the slot (1.25) is no parse; two extra words before "find" (2.0) is.
  CHECK(tolerant_cost("find {thing}", "help me find my slippers") ==
        2 * mi::TolerantCosts::kExtraWord);
  // Nor the other way round: a word missing after the slot is not inside it.
  CHECK(tolerant_cost("{thing} is on", "the kitchen light on") ==
        mi::TolerantCosts::kMissingWord);
  CHECK(tolerant_cost("{thing} is on", "is on") == mi::TolerantCosts::kMissingSlot);
}

TEST_CASE("normalise: contractions, spellings, ordinals, time formats") {
  CHECK(mi::normalize("What's the time?") == Words{"what", "is", "the", "time"});
  CHECK(mi::normalize("I'd like a reminder") == Words{"i", "would", "like", "a", "reminder"});
  CHECK(mi::normalize("don't, can't, won't") ==
        Words{"do", "not", "cannot", "will", "not"});
  CHECK(mi::normalize("my mum's keys") == Words{"my", "mum's", "keys"});  // possessive kept
  CHECK(mi::normalize("favourite colour") == Words{"favorite", "color"});
  CHECK(mi::normalize("the third of May") == Words{"the", "3rd", "of", "may"});
  CHECK(mi::normalize("wait a second") == Words{"wait", "a", "second"});  // a unit, not 2nd
  CHECK(mi::normalize("6am") == Words{"6", "am"});
  CHECK(mi::normalize("6:30 a.m.") == Words{"6:30", "am"});
  CHECK(mi::normalize("half past two") == Words{"half", "past", "2"});
  CHECK(mi::normalize("quarter to nine") == Words{"quarter", "to", "9"});
  CHECK(mi::normalize("10 mins") == Words{"10", "minutes"});
  CHECK(mi::normalize("how ya doin") == Words{"how", "you", "doing"});
}

TEST_CASE("politeness and filler around a request are dropped, never the whole request") {
  auto strip = [](const char* text) { return mi::strip_politeness(mi::normalize(text)); };
  CHECK(strip("Hey Marvin, could you please tell me the time?") == Words{"tell", "me", "the", "time"});
  CHECK(strip("Marvin, I need you to set a timer for me") == Words{"set", "a", "timer"});
  CHECK(strip("can you remind me to call Anna please, thanks") ==
        Words{"remind", "me", "to", "call", "anna"});
  CHECK(strip("so um what time is it marvin") == Words{"what", "time", "is", "it"});
  CHECK(strip("thank you") == Words{"thank", "you"});
  CHECK(strip("please") == Words{"please"});
}

TEST_CASE("tolerant matching: extra, missing, stemmed and synonym words each cost") {
  CHECK(tolerant_cost("what is the time", "what is the time") == 0.0F);
  CHECK(tolerant_cost("what is the time", "so what is the time now") ==
        2 * mi::TolerantCosts::kExtraWord);
  CHECK(tolerant_cost("what is the time", "what is time") == mi::TolerantCosts::kMissingWord);
  CHECK(tolerant_cost("list my reminder", "list my reminders") == mi::TolerantCosts::kStem);
  CHECK(tolerant_cost("what time is it", "what time it is") == mi::TolerantCosts::kSwap);
  CHECK(tolerant_cost("what is the time", "the weather in paris tomorrow please") < 0);
  // A synonym the skill declares: "alarm" for "reminder".
  mi::Vocabulary probe;
  mi::CompiledTemplate compiled;
  mi::TemplateSyntaxError error;
  REQUIRE(mi::compile_template("cancel the reminder", {}, {}, probe, compiled, error));
  mi::SynonymTable synonyms{{"alarm", {probe.find("reminder")}}};
  CHECK(tolerant_cost("cancel the reminder", "cancel the alarm", synonyms) ==
        mi::TolerantCosts::kSynonym);
  CHECK(tolerant_cost("cancel the reminder", "cancel the alarm") ==
        mi::TolerantCosts::kExtraWord + mi::TolerantCosts::kMissingWord);
}

TEST_CASE("people's phrasings reach the right intent with the right slots") {
  Interpreter in = small_home();
  Context context = fixed_context();
  struct Case {
    const char* text;
    const char* intent;
  };
  for (Case c : {Case{"what's the time", "time"}, Case{"Hey, what is the time?", "time"},
                 Case{"Could you tell me what time it is?", "time"},
                 Case{"set a timer for 10 minutes", "set"},
                 Case{"please start a timer for five minutes", "set"}}) {
    std::string text = c.text;
    CAPTURE(text);
    Understanding u = in.understand(c.text, context);
    REQUIRE(u.outcome == Understanding::Outcome::kMatch);
    CHECK(u.match->intent == c.intent);
  }
  auto alarm = in.match("set alarm at 6:30 a.m", context);
  REQUIRE(alarm);
  CHECK(alarm->intent == "add");
  REQUIRE(alarm->slots.count("when"));
  CHECK(alarm->slots.at("when").value.at("at") == "2026-11-26T06:30");
  auto timer = in.match("could you please start a timer for 10 minutes", context);
  REQUIRE(timer);
  CHECK(timer->slots.at("duration").value == 600);
}

TEST_CASE("the same skills give the same model and the same answers") {
  Interpreter a = small_home();
  Interpreter b = small_home();
  CHECK(a.build_model() == b.build_model());
  Context context = fixed_context();
  for (std::string text : {"what is the time", "could you start a countdown", "is it raining",
                           "remind me about the dentist"}) {
    CAPTURE(text);
    Understanding ua = a.understand(text, context);
    Understanding ub = b.understand(text, context);
    REQUIRE(ua.ranking.size() == ub.ranking.size());
    for (std::size_t i = 0; i < ua.ranking.size(); ++i) {
      CHECK(ua.ranking[i].intent == ub.ranking[i].intent);
      CHECK(ua.ranking[i].probability == ub.ranking[i].probability);  // bit for bit
    }
    CHECK(ua.outcome == ub.outcome);
  }
  // Removing and re-adding a skill rebuilds the same model.
  Interpreter c = small_home();
  c.remove_skill("timer");
  CHECK(c.understand("set a timer for 10 minutes", context).outcome !=
        Understanding::Outcome::kMatch);
}

TEST_CASE("the threshold declines requests no skill serves") {
  Interpreter in = small_home();
  Context context = fixed_context();
  // Written for this test; none of them is in the model's out-of-scope sentences.
  const char* outside[] = {
      "what's the weather like in madrid",  "play something by the beatles",
      "how do i bake sourdough bread",      "who won the world cup in 2014",
      "translate cheese into french",        "what is the square root of 81",
      "book a table for four tonight",       "how much is my electricity bill",
      "tell me about the roman empire",      "recommend a podcast about history",
      "where is the nearest petrol station", "how many legs does a spider have",
      "what's the stock price of apple",     "turn the tv to channel 4",
      "order new printer ink",               "is it safe to swim after eating",
      "what is the speed of light",          "write me a limerick",
      "how do i fix a leaking tap",          "what's a good name for a goldfish",
  };
  int acted = 0;
  for (std::string text : outside) {
    CAPTURE(text);
    Understanding u = in.understand(text, context);
    if (u.outcome == Understanding::Outcome::kMatch) ++acted;
    CHECK(u.outcome != Understanding::Outcome::kMatch);
  }
  CHECK(acted == 0);
}

TEST_CASE("a request after a remark is the request; a condition, a question or a negation is not") {
  Interpreter in = small_home();
  Context context = fixed_context();
  Understanding after = in.understand("I'm going to be busy, set a timer for 10 minutes", context);
  REQUIRE(after.outcome == Understanding::Outcome::kMatch);
  CHECK(after.match->intent == "set");
  CHECK(after.match->slots.at("duration").value == 600);
  CHECK(after.reason == "a request after a lead-in (\"i am going to be busy\")");
  CHECK(after.words.front() == "i");  // the whole utterance, as said
  // What the lead-in changes: never acted on through the rest alone.
  for (std::string text : {"if the cake burns set a timer for 10 minutes",
                           "how do i set a timer for 10 minutes",
                           "ask anna to set a timer for 10 minutes",
                           "do you think i should set a timer for 10 minutes",
                           "after dinner set a timer for 10 minutes"}) {
    CAPTURE(text);
    Understanding u = in.understand(text, context);
    CHECK(u.reason.find("lead-in") == std::string::npos);
  }
}

TEST_CASE("a request not to do something acts only through a template that says so") {
  Interpreter in = small_home();
  Context context = fixed_context();
  for (std::string text : {"don't set a timer for 10 minutes", "please do not set a timer",
                           "never tell me the time", "Marvin, don't remind me to call mum"}) {
    CAPTURE(text);
    Understanding u = in.understand(text, context);
    CHECK(u.outcome == Understanding::Outcome::kNone);
    CHECK(u.negated);
    CHECK(u.choices.empty());
  }
  // The skill's own template says it: acted on.
  mi::IntentSpec keep{"keeper", "keep", {"don't forget {task}"}, {{"task", SlotType::kText, {}}}};
  in.add(keep);
  Understanding kept = in.understand("don't forget the bins", context);
  REQUIRE(kept.outcome == Understanding::Outcome::kMatch);
  CHECK(kept.match->intent == "keep");
  CHECK_FALSE(kept.negated);
  // Without the negation, the same words are a request.
  CHECK_FALSE(in.understand("set a timer for 10 minutes", context).negated);
}

TEST_CASE("a forgiving parse needs two of the template's own words, not one plus free text") {
  Interpreter in = small_home();
  mi::IntentSpec query{"devices",
                       "query",
                       {"(is|are) [the] {device} (on|off)"},
                       {{"device", SlotType::kText, {}}}};
  query.examples = {"is the kitchen light on", "are the lights off", "is the fan still on",
                    "is the tv on", "are the bedroom lamps on"};
  in.add(query);
  Context context = fixed_context();
  Understanding on = in.understand("is the hall light on", context);
  REQUIRE(on.outcome == Understanding::Outcome::kMatch);
  CHECK(on.match->intent == "query");
  // Written for this test: yes/no questions about the world, not about devices.
  // Each fits "(is|are) {device} (on|off)" at cost 1.25 (the last word for "on").
  for (const char* text : {"is butter healthy", "are penguins birds", "is the fan broken"}) {
    CAPTURE(text);
    Understanding u = in.understand(text, context);
    CHECK(u.outcome != Understanding::Outcome::kMatch);
  }
}

TEST_CASE("bad input: a clear reason, no match, and the interpreter unchanged") {
  Interpreter in = small_home();
  Context context = fixed_context();
  CHECK(in.understand("", context).reason == "no words");
  CHECK(in.understand(" ?!, ", context).reason == "no words");
  std::string many_words;
  for (int i = 0; i < 65; ++i) many_words += "time ";
  Understanding wordy = in.understand(many_words, context);
  CHECK(wordy.outcome == Understanding::Outcome::kNone);
  CHECK(wordy.reason == "too long (65 words, at most 64)");
  std::string spaced;
  for (int i = 0; i < 200000; ++i) spaced += "time ";  // a 1 MB line
  Understanding long_line = in.understand(spaced, context);
  CHECK(long_line.outcome == Understanding::Outcome::kNone);
  CHECK(long_line.reason == "too long (1000000 bytes, at most 4096)");
  CHECK(long_line.words.empty());  // refused before any work on it
  CHECK(in.builtin("stop" + std::string(5000, ' ')) == Builtin::kNone);
  CHECK(in.builtin("stop" + std::string(4000, ' ')) == Builtin::kStop);
  CHECK_FALSE(in.match(std::string(1 << 20, 'x'), context));
  std::string binary;
  for (int i = 0; i < 1024; ++i) binary.push_back(static_cast<char>((i * 37) % 256));
  CHECK_FALSE(in.match(binary, context));
  CHECK_FALSE(in.match("\xc3\x28 \xa0\xa1 \xf0\x28\x8c\xbc", context));  // invalid UTF-8
  CHECK(in.size() == 3);
  CHECK(in.match("what time is it", context)->intent == "time");
}

TEST_CASE("an example sentence of an intent without slots, said word for word, is that intent") {
  Interpreter in = small_home();
  mi::IntentSpec hello{"greeter", "hello", {"hello [there]", "good morning"}, {}};
  // "what is ..." is mostly asked of other intents; the author says this one greets.
  hello.examples = {"what's new with you", "how goes it", "yo"};
  in.add(hello);
  const Context context = fixed_context();
  for (const char* text : {"what's new with you", "hey, what is new with you?", "how goes it",
                           "please yo"}) {
    const std::string said = text;
    CAPTURE(said);
    Understanding u = in.understand(text, context);
    REQUIRE(u.outcome == Understanding::Outcome::kMatch);
    CHECK(u.match->intent == "hello");
    CHECK(u.reason == "an example sentence word for word");
  }
  // An example two intents share decides nothing.
  mi::IntentSpec wave{"waver", "wave", {"wave at me"}, {}};
  wave.examples = {"how goes it"};
  in.add(wave);
  CHECK(in.understand("how goes it", context).reason != "an example sentence word for word");
  CHECK(in.understand("yo", context).reason == "an example sentence word for word");
  // Only word for word: more words go to the model as before.
  Understanding longer = in.understand("what is new with you and the weather", context);
  CHECK(longer.reason != "an example sentence word for word");
  // An intent with slots is matched through its templates, which fill them: its examples
  // are not taken word for word (the slots would be lost).
  Understanding reminder = in.understand("wake me up at 6", context);
  CHECK(reminder.reason != "an example sentence word for word");
}
