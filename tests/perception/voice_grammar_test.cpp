// The host's grammars from skill manifests and personal data (core/app/voice_grammar.h):
// contacts and reminders become slot phrases, questions get the grammar of their slot, and
// a change in contacts changes the grammar. Plain text checks; and, last, what a voice style
// ("speak slower") does to espeak-ng's output.
#include <doctest/doctest.h>

#include <string>
#include <vector>

#include "app/voice_grammar.h"
#include "app/voice_host.h"
#include "skills/in_memory_personal_data.h"
#include "speech_fixture.h"
#include "support/text.h"

using namespace marvin;
using app::SkillPhrases;

namespace {

skills::SlotDecl slot(const std::string& name, skills::SlotKind kind, const std::string& question) {
  skills::SlotDecl s;
  s.name = name;
  s.kind = kind;
  s.required = !question.empty();
  s.question = question;
  return s;
}

SkillPhrases phrases() {
  SkillPhrases p;
  p.intents.push_back({"schedule.remind",
                       {"remind me to {task} {when}", "remind me to {task}"},
                       {slot("task", skills::SlotKind::kText, "What should I remind you of?"),
                        slot("when", skills::SlotKind::kDateTime, "When should I remind you?")}});
  p.intents.push_back({"phone.call", {"call {who}"}, {slot("who", skills::SlotKind::kContact, "Whom should I call?")}});
  for (const auto& intent : p.intents) {
    for (const auto& s : intent.slots) p.questions.push_back({s.question, s, false});
  }
  p.questions.push_back({"Shall I call {who}?", {}, true});
  return p;
}

using marvin::test_support::contains;

}  // namespace

TEST_CASE("command grammar: contacts, stored reminders and everyday tasks are the slot phrases") {
  skills::InMemoryPersonalData data;
  data::Contact anna;
  anna.name = "Anna Schmidt";
  anna.aliases = {"my daughter"};
  data.add_contact(anna);
  data::Reminder orchids;
  orchids.title = "water the orchids";
  orchids.first_fire_utc_ms = 1'800'000'000'000;
  orchids.next_fire_utc_ms = orchids.first_fire_utc_ms;
  orchids.time_zone = "UTC";
  data.add_reminder(orchids);

  const app::SlotValues values = app::current_slot_values(data);
  // Full name, alias, and the first name the interpreter resolves on its own.
  CHECK(values.contacts == std::vector<std::string>{"Anna Schmidt", "my daughter", "anna"});
  const std::string jsgf = app::command_grammar(phrases(), values, {}).jsgf;
  CHECK(contains(jsgf, "anna schmidt | my daughter | anna"));
  CHECK(contains(jsgf, "water the orchids"));  // a stored reminder's title
  CHECK(contains(jsgf, "take my pills"));      // an everyday task
  // The task is one of those phrases, not the free-text loop (see voice_grammar.h).
  CHECK(contains(jsgf, "remind me to <i0_schedule_remind_task>"));
  CHECK_FALSE(contains(jsgf, "remind me to <free_text>"));
  // Every sentence may start with the wake word (the rest of it, reported early).
  CHECK(contains(jsgf, "public <command> = [marvin] ("));

  // A new contact changes the values, so the host regenerates the grammar.
  data::Contact peter;
  peter.name = "Peter";
  data.add_contact(peter);
  const app::SlotValues after = app::current_slot_values(data);
  CHECK_FALSE(after == values);
  CHECK(contains(app::command_grammar(phrases(), after, {}).jsgf, "peter"));
  CHECK(app::current_slot_values(data) == after);  // nothing changed: same values
}

TEST_CASE("answer grammar: the slot asked for, yes/no for a confirmation, none for the unknown") {
  skills::InMemoryPersonalData data;
  data::Contact bob;
  bob.name = "Bob";
  data.add_contact(bob);
  const app::SlotValues values = app::current_slot_values(data);
  const SkillPhrases p = phrases();

  const std::string when = app::answer_grammar(p, values, "When should I remind you?", {});
  CHECK(contains(when, "<datetime>"));
  CHECK(contains(when, "<conversation>"));  // "stop", "never mind" still work
  CHECK_FALSE(contains(when, "remind me"));  // not the command grammar
  // Asked again after a bad answer.
  CHECK(app::answer_grammar(p, values, "Sorry, I didn't get that. When should I remind you?", {}) ==
        when);

  const std::string who = app::answer_grammar(p, values, "Whom should I call?", {});
  CHECK(contains(who, "bob"));
  CHECK_FALSE(contains(who, "remind me"));

  const std::string yes_no = app::answer_grammar(p, values, "Shall I call Bob?", {});
  CHECK(contains(yes_no, "yes"));
  CHECK_FALSE(contains(yes_no, "bob"));
  CHECK(app::answer_grammar(p, values, "Please answer yes or no. Shall I call Bob?", {}) == yes_no);

  CHECK(app::answer_grammar(p, values, "Which colour do you like?", {}).empty());
}

TEST_CASE("command grammar: the places the robot can go to are slot phrases too") {
  struct Places : navigation::GoingPlaces {
    navigation::GoResult go_to(std::string_view, const navigation::WaitFn&) override { return {}; }
    void stop() override {}
    std::optional<std::string> where_am_i() override { return std::nullopt; }
    std::vector<std::string> place_names() const override { return {"kitchen", "the kitchen"}; }
  } places;
  app::SlotValues values;
  app::add_place_names(nullptr, values);
  CHECK(values.text_phrases.empty());
  app::add_place_names(&places, values);
  CHECK(values.text_phrases == std::vector<std::string>{"kitchen", "the kitchen"});
  CHECK(contains(app::command_grammar(phrases(), values, {}).jsgf, "the kitchen"));
}

TEST_CASE("a voice style: slower speaks the same sentence longer, louder louder; within bounds") {
  using marvin::app::styled_voice;
  using Style = marvin::skills::Manager::VoiceStyle;
  const marvin::perception::SynthesisOptions base;  // 160 wpm, volume 100
  CHECK(styled_voice(base, Style{-2, 0}).rate_wpm == 120);
  CHECK(styled_voice(base, Style{0, 3}).volume == 175);
  CHECK(styled_voice(base, Style{0, -3}).volume == 25);
  marvin::perception::SynthesisOptions slow_base = base;
  slow_base.rate_wpm = 90;
  CHECK(styled_voice(slow_base, Style{-3, 0}).rate_wpm == 80);  // espeak-ng's lowest

  const std::string sentence = "It's five past three in the afternoon.";
  using marvin::perception::testing::rms;
  const auto normal = marvin::perception::SpeechSynthesizer(base).synthesize(sentence);
  const auto slower =
      marvin::perception::SpeechSynthesizer(styled_voice(base, Style{-2, 0})).synthesize(sentence);
  const auto louder =
      marvin::perception::SpeechSynthesizer(styled_voice(base, Style{0, 2})).synthesize(sentence);
  CHECK(double(slower.size()) > 1.15 * double(normal.size()));
  CHECK(rms(louder) > 1.2 * rms(normal));
}
