#include <doctest/doctest.h>

#include <string>
#include <vector>

#include "perception/command_grammar.h"
#include "support/text.h"

using namespace marvin::perception;

namespace {

using marvin::test_support::contains;

GrammarOptions bare() {
  GrammarOptions options;
  options.conversation_phrases.clear();
  options.accept_bare_slot_values = false;
  return options;
}

}  // namespace

TEST_CASE("words are normalised like the interpreter's") {
  CHECK(grammar_words("What's the time, Marvin?") ==
        std::vector<std::string>{"what's", "the", "time", "marvin"});
  CHECK(grammar_words("at 8 or 25 past 10") ==
        std::vector<std::string>{"at", "eight", "or", "twenty", "five", "past", "ten"});
  CHECK(grammar_words("call 'Anna'") == std::vector<std::string>{"call", "anna"});
}

TEST_CASE("alternatives, optionals and slots become JSGF") {
  std::vector<GrammarIntent> intents = {
      {"lights.on", {"(turn|switch) on [the] {device}", "lights on"},
       {{"device", SlotKind::kPhrases, {"lamp", "Living Room Light", "fan"}}}},
      {"time.query", {"what time is it", "what's the time [please]"}, {}},
  };
  const GrammarResult result = build_command_grammar(intents, bare());
  CAPTURE(result.jsgf);
  CHECK(contains(result.jsgf, "#JSGF V1.0;"));
  CHECK(contains(result.jsgf, "public <command> = <i0_lights_on> | <i1_time_query>;"));
  CHECK(contains(result.jsgf, "<i0_lights_on_device> = lamp | living room light | fan;"));
  CHECK(contains(result.jsgf,
                 "<i0_lights_on> = (turn | switch) on [the] <i0_lights_on_device> | lights on;"));
  CHECK(contains(result.jsgf, "<i1_time_query> = what time is it | what's the time [please];"));
  CHECK(result.templates_used == 4);
  CHECK(result.skipped.empty());
}

TEST_CASE("typed slots refer to the built-in rules") {
  std::vector<GrammarIntent> intents = {
      {"timer", {"set [a] timer for {duration}"}, {{"duration", SlotKind::kDuration, {}}}},
      {"remind", {"remind me to {task} {when}"},
       {{"task", SlotKind::kText, {}}, {"when", SlotKind::kDateTime, {}}}},
      {"volume", {"volume {level}"}, {{"level", SlotKind::kNumber, {}}}},
  };
  const GrammarResult result = build_command_grammar(intents, bare());
  CAPTURE(result.jsgf);
  CHECK(contains(result.jsgf, "<i0_timer> = set [a] timer for <duration>;"));
  CHECK(contains(result.jsgf, "<i1_remind> = remind me to <free_text> <datetime>;"));
  CHECK(contains(result.jsgf, "<i2_volume> = volume <number>;"));
  CHECK(contains(result.jsgf, "<free_text> = <free_word>+;"));
  CHECK(contains(result.jsgf, "<datetime> = "));
  CHECK(contains(result.jsgf, "<number> = "));
  // A part of the day after a day, as the time parser reads it ("tomorrow morning").
  CHECK(contains(result.jsgf, "tomorrow [<t_daypart>]"));
  CHECK(contains(result.jsgf, "<t_daypart> = (morning | afternoon | evening | night);"));
  // Template words join the free-text vocabulary.
  CHECK(contains(result.jsgf, " remind |"));
}

TEST_CASE("words the dictionary lacks are left out and reported") {
  std::vector<GrammarIntent> intents = {
      {"call", {"(call|zorgle) {contact}", "phone {contact} [blimp]", "ring ring zorgle"},
       {{"contact", SlotKind::kPhrases, {"anna", "xqzt"}}}},
  };
  auto known = [](std::string_view w) { return w != "zorgle" && w != "xqzt" && w != "blimp"; };
  const GrammarResult result = build_command_grammar(intents, bare(), known);
  CAPTURE(result.jsgf);
  CHECK(contains(result.jsgf, "<i0_call_contact> = anna;"));
  CHECK(contains(result.jsgf, "<i0_call> = call <i0_call_contact> | phone <i0_call_contact>;"));
  CHECK_FALSE(contains(result.jsgf, "zorgle"));
  CHECK(result.templates_used == 2);
  std::string skipped;
  for (const std::string& line : result.skipped) skipped += line + "\n";
  CAPTURE(skipped);
  CHECK(contains(skipped, "\"zorgle\" is not in the dictionary (intent call, template 1"));
  CHECK(contains(skipped, "\"blimp\" is not in the dictionary (intent call, template 2"));
  CHECK(contains(skipped, "\"xqzt\" is not in the dictionary (intent call, slot {contact}"));
}

TEST_CASE("regenerating with new slot values changes the grammar") {
  std::vector<GrammarIntent> intents = {
      {"call", {"call {contact}"}, {{"contact", SlotKind::kPhrases, {"anna"}}}}};
  const std::string before = build_command_grammar(intents, bare()).jsgf;
  intents[0].slots[0].phrases.push_back("peter");
  const std::string after = build_command_grammar(intents, bare()).jsgf;
  CHECK_FALSE(contains(before, "peter"));
  CHECK(contains(after, "<i0_call_contact> = anna | peter;"));
}

TEST_CASE("conversation phrases and bare slot values are accepted as answers") {
  std::vector<GrammarIntent> intents = {
      {"call", {"call {contact}"}, {{"contact", SlotKind::kPhrases, {"anna"}}}}};
  GrammarOptions options;
  CHECK_FALSE(options.accept_bare_slot_values);
  CHECK_FALSE(contains(build_command_grammar(intents, options).jsgf, "<command> = <i0_call_contact>"));
  options.accept_bare_slot_values = true;
  const GrammarResult result = build_command_grammar(intents, options);
  CAPTURE(result.jsgf);
  CHECK(contains(result.jsgf, "public <command> = <i0_call_contact> | <i0_call> | <conversation>;"));
  CHECK(contains(result.jsgf, "<conversation> = stop | cancel | never mind | yes"));
}

TEST_CASE("template errors name intent, template and column") {
  std::vector<GrammarIntent> intents = {{"broken", {"turn (on|off"}, {}}};
  CHECK_THROWS_WITH_AS(build_command_grammar(intents, bare()),
                       "intent broken, template 1 \"turn (on|off\", column 13: missing ')'",
                       GrammarError);
  intents = {{"broken", {"call {who}"}, {}}};
  CHECK_THROWS_WITH_AS(build_command_grammar(intents, bare()),
                       doctest::Contains("slot {who} is not declared"), GrammarError);
  intents = {{"broken", {"stop ]"}, {}}};
  CHECK_THROWS_WITH_AS(build_command_grammar(intents, bare()), doctest::Contains("unbalanced ']'"),
                       GrammarError);
  intents.clear();
  CHECK_THROWS_WITH_AS(build_command_grammar(intents, bare()), doctest::Contains("empty"),
                       GrammarError);
}

TEST_CASE("politeness is accepted around commands, not around conversation phrases") {
  std::vector<GrammarIntent> intents = {{"time.query", {"what time is it"}, {}}};
  GrammarOptions options = bare();
  options.conversation_phrases = {"stop"};
  options.polite_before = GrammarOptions::default_polite_before();
  options.polite_after = GrammarOptions::default_polite_after();
  const GrammarResult result = build_command_grammar(intents, options);
  CAPTURE(result.jsgf);
  CHECK(contains(result.jsgf,
                 "public <command> = <polite_before> <commands> <polite_after> | <conversation>;"));
  CHECK(contains(result.jsgf, "<commands> = <i0_time_query>;"));
  CHECK(contains(result.jsgf,
                 "<polite_before> = [hey] [(could | can | would | will) you] [please];"));
  CHECK(contains(result.jsgf, "<polite_after> = [please] [thanks | thank you];"));
  // Words the recognizer lacks are left out of the politeness like anywhere else.
  const GrammarResult no_hey = build_command_grammar(
      intents, options, [](std::string_view word) { return word != "hey"; });
  CHECK_FALSE(contains(no_hey.jsgf, "[hey]"));
}
