#include <doctest/doctest.h>

#include <string>

#include "interpret/interpreter.h"
#include "interpret/template.h"

using namespace marvin::interpret;

namespace {

IntentSpec spec_with(std::string text) {
  IntentSpec spec;
  spec.skill_id = "timer";
  spec.intent = "set";
  spec.templates = {std::move(text)};
  spec.slots = {{"duration", SlotType::kDuration, {}}, {"what", SlotType::kText, {}}};
  return spec;
}

// The message add() throws for a single-template spec, or "" if it does not throw.
std::string error_of(const std::string& text) {
  Interpreter interpreter;
  try {
    interpreter.add(spec_with(text));
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("template compile: program shape and bounds") {
  Vocabulary vocabulary;
  CompiledTemplate compiled;
  TemplateSyntaxError error;
  REQUIRE(compile_template("(set|start) [a] timer for {duration}", {"duration"}, {12},
                           vocabulary, compiled, error));
  CHECK(compiled.min_words == 4);   // set timer for X
  CHECK(compiled.max_words == 16);  // start a timer for + 12
  CHECK(compiled.literal_words_max == 4);
  // Only "timer" and "for" are in every sentence.
  REQUIRE(compiled.required_words.size() == 2);
  CHECK(compiled.program.back().op == Instruction::Op::kMatch);
  // Literal words are normalised like utterances.
  CHECK(vocabulary.find("timer") != Vocabulary::kUnknown);
  REQUIRE(compile_template("Set volume to Twenty-Five!", {}, {}, vocabulary, compiled, error));
  CHECK(vocabulary.find("25") != Vocabulary::kUnknown);
  CHECK(compiled.min_words == 4);
  CHECK(compiled.max_words == 4);
}

TEST_CASE("template errors name skill, intent, template and column") {
  std::string message = error_of("set a timer for {duration");
  CHECK(message ==
        "skill \"timer\", intent \"set\", template \"set a timer for {duration\": column 17: "
        "'{' is never closed (expected '}' after the slot name)");

  struct Case {
    const char* text;
    const char* expected;  // substring after the template part
  };
  const Case cases[] = {
      {"turn (on|off the lamp", "column 6: '(' is never closed (expected ')')"},
      {"turn [on the lamp", "column 6: '[' is never closed (expected ']')"},
      {"turn on] the lamp", "column 8: unexpected ']' (nothing to close)"},
      {"turn on) the lamp", "column 8: unexpected ')' (nothing to close)"},
      {"set } timer", "column 5: unexpected '}' (nothing to close)"},
      {"call {person}", "column 6: slot {person} is not declared in the intent's slots"},
      {"(a||b)", "column 4: empty alternative in the group opened at column 1"},
      {"x (|b)", "column 4: empty alternative in the group opened at column 3"},
      {"x []", "column 4: empty choice in the optional opened at column 3"},
      {"(a|b]", "column 5: unexpected ']' inside the group opened at column 1 (expected ')')"},
      {"[please]", "column 1: template can match an empty utterance"},
      {"", "column 1: template is empty"},
      {" ?! ", "column 1: template is empty"},
      {"a|b", "column 2: '|' outside a group"},
      {"{what} and {what}", "column 12: slot {what} is used twice in one template"},
      {"{bad-name}", "column 5: invalid character '-' in slot name"},
      {"{}", "column 1: empty slot name in '{}'"},
      {"set {duration timer", "column 5: '{' is never closed"},
      {"set {dura(tion} timer", "column 5: '{' is never closed"},
  };
  for (const Case& c : cases) {
    CAPTURE(c.text);
    std::string got = error_of(c.text);
    CHECK(got.find(std::string("template \"") + c.text + "\": ") != std::string::npos);
    CHECK(got.find(c.expected) != std::string::npos);
  }
}

TEST_CASE("valid templates compile") {
  const char* ok[] = {"set [a] timer for {duration}",
                      "(set|start) [(a|the)] timer [for] {duration}",
                      "[please] remind me [to] {what}",
                      "{what}",
                      "[a] b",
                      "((nested|groups) [deep [er]])",
                      "{ duration } timer"};
  for (const char* text : ok) {
    CAPTURE(text);
    CHECK(error_of(text) == "");
  }
}

TEST_CASE("add: bad spec leaves the interpreter unchanged") {
  Interpreter interpreter;
  IntentSpec good = spec_with("set [a] timer for {duration}");
  interpreter.add(good);
  Context context;

  IntentSpec bad = spec_with("stop the music");
  bad.skill_id = "music";
  bad.intent = "stop";
  bad.templates.push_back("play (some|the music");
  CHECK_THROWS_WITH_AS(interpreter.add(bad),
                       doctest::Contains("skill \"music\", intent \"stop\", template \"play "
                                         "(some|the music\": column 6"),
                       std::runtime_error);
  CHECK(interpreter.size() == 1);
  CHECK_FALSE(interpreter.match("stop the music", context));  // first template not added
  CHECK(interpreter.match("set a timer for 5 minutes", context));

  IntentSpec duplicate_slot = spec_with("x {what}");
  duplicate_slot.slots.push_back({"what", SlotType::kNumber, {}});
  CHECK_THROWS_WITH(interpreter.add(duplicate_slot),
                    "skill \"timer\", intent \"set\": slot \"what\" is declared twice");
  IntentSpec empty_list = spec_with("turn on {device}");
  empty_list.slots = {{"device", SlotType::kList, {}}};
  CHECK_THROWS_WITH(interpreter.add(empty_list),
                    "skill \"timer\", intent \"set\": list slot \"device\" has no values");
  IntentSpec no_id = spec_with("x");
  no_id.skill_id.clear();
  CHECK_THROWS_WITH(interpreter.add(no_id), doctest::Contains("empty skill id"));
  IntentSpec no_templates = spec_with("x");
  no_templates.templates.clear();
  CHECK_THROWS_WITH(interpreter.add(no_templates), doctest::Contains("no templates"));
  CHECK(interpreter.size() == 1);
}

TEST_CASE("slot type names round-trip") {
  for (SlotType type : {SlotType::kNumber, SlotType::kDuration, SlotType::kDateTime,
                        SlotType::kContact, SlotType::kList, SlotType::kText}) {
    CHECK(slot_type_from_string(to_string(type)) == type);
  }
  CHECK_FALSE(slot_type_from_string("date"));
}
