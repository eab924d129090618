#include <date/date.h>
#include <doctest/doctest.h>

#include <chrono>
#include <string>

#include "interpret/interpreter.h"
#include "interpret/voice_change.h"

using namespace marvin::interpret;
using namespace date::literals;

namespace {

// Friday 2024-03-29 10:00 in Berlin.
Context home_context() {
  Context context;
  context.now_utc_ms =
      std::chrono::duration_cast<std::chrono::milliseconds>(
          (date::sys_days{2024_y / 3 / 29} + std::chrono::hours(9)).time_since_epoch())
          .count();
  context.time_zone = "Europe/Berlin";
  context.contact_names = {"Anna Schmidt", "Bob", "Dr. Meyer", "Anna Weber"};
  return context;
}

Interpreter home_interpreter() {
  Interpreter interpreter;
  interpreter.add(
      {"time", "query", {"what time is it", "what's the time", "(tell me|what is) the time"}, {}});
  interpreter.add({"timer",
                   "set",
                   {"(set|start) [a] timer for {duration}", "{duration} timer"},
                   {{"duration", SlotType::kDuration, {}}}});
  interpreter.add({"reminders",
                   "add",
                   {"remind me to {task} {when}", "remind me {when} to {task}"},
                   {{"task", SlotType::kText, {}}, {"when", SlotType::kDateTime, {}}}});
  interpreter.add({"lights",
                   "switch",
                   {"turn (on|off) [the] {device}", "(switch|turn) [the] {device} (on|off)"},
                   {{"device", SlotType::kList, {"lamp", "fan", "Living Room Light"}}}});
  interpreter.add(
      {"phone", "call", {"(call|phone|ring) {who}"}, {{"who", SlotType::kContact, {}}}});
  interpreter.add({"volume",
                   "set",
                   {"set [the] volume to {level} [percent]"},
                   {{"level", SlotType::kNumber, {}}}});
  interpreter.add(
      {"notes", "take", {"(take|make) a note [that] {text}"}, {{"text", SlotType::kText, {}}}});
  return interpreter;
}

}  // namespace

TEST_CASE("matching: utterance -> intent + slots") {
  Interpreter interpreter = home_interpreter();
  Context context = home_context();
  struct Case {
    const char* utterance;
    const char* skill;
    const char* intent;
    const char* slot;      // one slot to check, or ""
    nlohmann::json value;  // its normalised value
  };
  const Case cases[] = {
      {"What time is it?", "time", "query", "", nullptr},
      {"Marvin, what time is it", "time", "query", "", nullptr},
      {"hey Marvin what's the time", "time", "query", "", nullptr},
      {"tell me the time please", "time", "query", "", nullptr},
      {"Set a timer for 20 minutes", "timer", "set", "duration", 1200},
      {"start timer for an hour and a half", "timer", "set", "duration", 5400},
      {"twenty five minutes timer", "timer", "set", "duration", 1500},
      {"Remind me to take my pills at 8 pm", "reminders", "add", "task", "take my pills"},
      {"remind me tomorrow at nine to call the doctor", "reminders", "add", "task",
       "call the doctor"},
      {"Turn on the living room light", "lights", "switch", "device", "Living Room Light"},
      {"switch the fan off", "lights", "switch", "device", "fan"},
      {"turn off lamp", "lights", "switch", "device", "lamp"},
      {"call Bob", "phone", "call", "who", "Bob"},
      {"phone Dr Meyer", "phone", "call", "who", "Dr. Meyer"},
      {"ring anna schmidt", "phone", "call", "who", "Anna Schmidt"},
      {"set the volume to twenty five", "volume", "set", "level", 25},
      {"set volume to 2.5 percent", "volume", "set", "level", 2.5},
      {"take a note that the milk is off", "notes", "take", "text", "the milk is off"},
      {"make a note buy one two three four five six seven", "notes", "take", "text",
       "buy 1 2 3 4 5 6 7"},
  };
  for (const Case& c : cases) {
    CAPTURE(c.utterance);
    auto match = interpreter.match(c.utterance, context);
    REQUIRE(match);
    CHECK(match->skill_id == c.skill);
    CHECK(match->intent == c.intent);
    if (std::string(c.slot).empty()) {
      CHECK(match->slots.empty());
    } else {
      REQUIRE(match->slots.count(c.slot) == 1);
      CHECK(match->slots.at(c.slot).value == c.value);
    }
  }

  auto reminder = interpreter.match("remind me to take my pills at 8 pm", context);
  REQUIRE(reminder);
  CHECK(reminder->slots.at("when").value["at"] == "2024-03-29T20:00");
  CHECK(reminder->slots.at("when").text == "at 8 pm");
  CHECK(reminder->literal_words == 3);
  auto morning = interpreter.match("remind me tomorrow at nine to call the doctor", context);
  REQUIRE(morning);
  CHECK(morning->slots.at("when").value["at"] == "2024-03-30T09:00");
  auto timer = interpreter.match("Set a timer for 20 minutes", context);
  REQUIRE(timer);
  CHECK(timer->slots.at("duration").text == "20 minutes");
  CHECK(timer->literal_words == 4);
}

TEST_CASE("matching: near misses do not match") {
  Interpreter interpreter = home_interpreter();
  Context context = home_context();
  const char* cases[] = {
      "",
      "marvin",
      "what time is it now",            // extra word
      "what time",                      // template not complete
      "time is it",                     // missing first word
      "set a timer",                    // required slot missing
      "set a timer for",                // slot empty
      "set a timer for twenty apples",  // not a duration
      "timer for 20 minutes",           // missing verb
      "turn on the toaster",            // not in the list
      "turn on the living room",        // partial list value
      "turn the lamp",                  // missing on/off
      "call Zorro",                     // not a contact
      "call Anna",                      // two contacts called Anna: ambiguous
      "set the volume to loud",         // not a number
      "set the volume to 5 6",          // two numbers
      "remind me to take my pills",     // no time
      "remind me to take my pills at 25 pm",
      "take a note",                                               // text needs a word
      "take a note one two three four five six seven eight nine",  // text is at most 8 words
      "please",
      "what is the weather",
  };
  for (const char* utterance : cases) {
    CAPTURE(utterance);
    CHECK_FALSE(interpreter.match_exact(utterance, context));
  }
}

TEST_CASE("matching: first names resolve when unique") {
  Interpreter interpreter = home_interpreter();
  Context context = home_context();
  context.contact_names = {"Anna Schmidt", "Bob"};
  auto match = interpreter.match("call anna", context);
  REQUIRE(match);
  CHECK(match->slots.at("who").value == "Anna Schmidt");
  CHECK(match->slots.at("who").text == "anna");
}

TEST_CASE("ranking: literal words beat wildcard text") {
  Interpreter interpreter;
  interpreter.add(
      {"search", "anything", {"turn on [the] {thing}"}, {{"thing", SlotType::kText, {}}}});
  interpreter.add({"radio", "on", {"turn on the radio"}, {}});
  Context context;
  auto match = interpreter.match("turn on the radio", context);
  REQUIRE(match);
  CHECK(match->skill_id == "radio");
  CHECK(match->literal_words == 4);
  // Without the literal template the wildcard one answers, and it prefers taking "the" as
  // a literal word (3 literal words) over putting it into the text.
  auto other = interpreter.match("turn on the kettle", context);
  REQUIRE(other);
  CHECK(other->skill_id == "search");
  CHECK(other->slots.at("thing").text == "kettle");
  CHECK(other->literal_words == 3);
}

TEST_CASE("ranking: a typed slot beats a text slot with the same literal words") {
  for (bool text_first : {true, false}) {
    CAPTURE(text_first);
    Interpreter interpreter;
    IntentSpec text{"notes", "timer_note", {"timer for {what}"}, {{"what", SlotType::kText, {}}}};
    IntentSpec typed{
        "timer", "set", {"timer for {duration}"}, {{"duration", SlotType::kDuration, {}}}};
    interpreter.add(text_first ? text : typed);
    interpreter.add(text_first ? typed : text);
    auto match = interpreter.match("timer for ten minutes", Context{});
    REQUIRE(match);
    CHECK(match->skill_id == "timer");
    auto fallback = interpreter.match("timer for the eggs", Context{});
    REQUIRE(fallback);
    CHECK(fallback->skill_id == "notes");
  }
}

TEST_CASE("ranking: templates that fit equally well go to the model's choice, every time") {
  // Both fit "play music" with the same literal words; the model, not the order the skills
  // were added in, decides (once the first registered won, and "is there someone in the
  // house" went to "is {what} in the house").
  IntentSpec a{"music", "play", {"play [some] music"}, {}, {"put on some music", "play a song"}};
  IntentSpec b{"radio", "play", {"play music"}, {}, {"tune the radio", "play the radio station"}};
  Interpreter ab;
  ab.add(a);
  ab.add(b);
  Interpreter ba;
  ba.add(b);
  ba.add(a);
  const std::string chosen = ab.match("play music", Context{})->skill_id;
  for (int i = 0; i < 20; ++i) {
    auto first = ab.match("play music", Context{});
    auto second = ba.match("play music", Context{});
    REQUIRE(first);
    REQUIRE(second);
    CHECK(first->skill_id == chosen);
    CHECK(second->skill_id == chosen);
  }
  // The one the model ranks higher.
  const Understanding u = ab.understand("play music", Context{});
  REQUIRE(u.match);
  CHECK(u.match->skill_id == chosen);
  REQUIRE_FALSE(u.ranking.empty());
  for (const RankedIntent& r : u.ranking) {
    if (r.skill_id == "music" || r.skill_id == "radio") {
      CHECK(r.skill_id == chosen);
      break;
    }
  }
  // With the optional word spoken, only "music" can match, whatever the order.
  CHECK(ba.match("play some music", Context{})->skill_id == "music");
  // Copies answer the same.
  Interpreter copy = ba;
  CHECK(copy.match("play music", Context{})->skill_id == chosen);
}

TEST_CASE("ranking: within a template the parse with more literal words wins") {
  Interpreter interpreter;
  interpreter.add({"reminders",
                   "add",
                   {"remind me [to] {task} [at] {when}"},
                   {{"task", SlotType::kText, {}}, {"when", SlotType::kDateTime, {}}}});
  auto match = interpreter.match("remind me to water the plants at 9 pm", home_context());
  REQUIRE(match);
  CHECK(match->slots.at("task").text == "water the plants");
  CHECK(match->slots.at("when").text == "9 pm");
  CHECK(match->literal_words == 4);
}

TEST_CASE("conflicts: sentences claimed by two skills") {
  Interpreter interpreter;
  interpreter.add(
      {"lights", "on", {"turn on [the] {device}"}, {{"device", SlotType::kList, {"lamp", "fan"}}}});
  interpreter.add({"power", "switch_on", {"(turn|switch) on the lamp"}, {}});
  interpreter.add({"lights", "on_again", {"turn on the fan"}, {}});  // same skill: fine
  interpreter.add({"kitchen", "on", {"turn on the kettle"}, {}});    // different words
  interpreter.add({"notes", "add", {"note {text}"}, {{"text", SlotType::kText, {}}}});
  interpreter.add({"memo", "add", {"note {body}", "memo {body}"}, {{"body", SlotType::kText, {}}}});
  std::vector<std::string> conflicts = interpreter.conflicts();
  REQUIRE(conflicts.size() == 2);
  CHECK(conflicts[0] ==
        "\"turn on the lamp\" is claimed by skill \"lights\" (intent on) and skill \"power\" "
        "(intent switch_on)");
  CHECK(conflicts[1] ==
        "\"note {text}\" is claimed by skill \"notes\" (intent add) and skill \"memo\" "
        "(intent add)");

  Interpreter clean = home_interpreter();
  CHECK(clean.conflicts().empty());
}

TEST_CASE("conflicts: counts further shared sentences") {
  Interpreter interpreter;
  interpreter.add({"a", "x", {"(play|start) [the] music"}, {}});
  interpreter.add({"b", "y", {"(play|start) the music"}, {}});
  auto conflicts = interpreter.conflicts();
  REQUIRE(conflicts.size() == 1);
  CHECK(conflicts[0] ==
        "\"play the music\" is claimed by skill \"a\" (intent x) and skill \"b\" (intent y) "
        "(and 1 more sentence)");
}

TEST_CASE("builtins: stop, yes, no, repeat") {
  Interpreter interpreter = home_interpreter();
  struct Case {
    const char* utterance;
    Builtin expected;
  };
  const Case cases[] = {
      {"stop", Builtin::kStop},
      {"Cancel!", Builtin::kStop},
      {"Marvin, stop", Builtin::kStop},
      {"never mind", Builtin::kStop},
      {"please stop", Builtin::kStop},
      {"hey marvin cancel that", Builtin::kStop},
      {"yes", Builtin::kYes},
      {"Yeah.", Builtin::kYes},
      {"sure", Builtin::kYes},
      {"yes please", Builtin::kYes},
      {"no", Builtin::kNo},
      {"Nope", Builtin::kNo},
      {"no thank you", Builtin::kNo},
      {"repeat", Builtin::kRepeat},
      {"say that again", Builtin::kRepeat},
      {"Marvin, say that again please", Builtin::kRepeat},
      {"", Builtin::kNone},
      {"marvin", Builtin::kNone},
      {"stop the music", Builtin::kNone},
      {"yes no", Builtin::kNone},
      {"what time is it", Builtin::kNone},
      {"please", Builtin::kNone},
      // After fillers and lead-ins; "never mind that" is stop, not "never".
      {"oh never mind that", Builtin::kStop},
      {"i want to cancel that", Builtin::kStop},
      {"um forget it", Builtin::kStop},
      {"scratch that", Builtin::kStop},
      {"actually yes", Builtin::kYes},
      {"sure thing", Builtin::kYes},
      {"well no", Builtin::kNo},
      {"not at all", Builtin::kNo},
      {"i want to cancel my dentist reminder", Builtin::kNone},
      {"oh stop the music", Builtin::kNone},
      {"i want to know the time", Builtin::kNone},
      // Declining in passing, and saying it again after a lead-in.
      {"I'll pass", Builtin::kNo},
      {"i will pass on that thanks", Builtin::kNo},
      {"no need", Builtin::kNo},
      {"I said no!", Builtin::kNo},
      {"i repeat, stop", Builtin::kStop},
      {"i told you to cancel it", Builtin::kStop},
      {"No, just cancel it", Builtin::kStop},
      {"no no stop", Builtin::kStop},
      {"no just cancel my dentist reminder", Builtin::kNone},
      {"pass the salt", Builtin::kNone},
      {"i told you to cancel my reminder", Builtin::kNone},
  };
  for (const Case& c : cases) {
    std::string utterance = c.utterance;
    CAPTURE(utterance);
    CHECK(interpreter.builtin(c.utterance) == c.expected);
  }
}

TEST_CASE("parse_slot: dialogue answers") {
  Interpreter interpreter;
  Context context = home_context();
  auto number = interpreter.parse_slot({"n", SlotType::kNumber, {}}, "It's eight", context);
  REQUIRE(number);
  CHECK(number->value == 8);
  CHECK(number->text == "8");
  auto when = interpreter.parse_slot({"when", SlotType::kDateTime, {}}, "at eight", context);
  REQUIRE(when);
  CHECK(when->value["at"] == "2024-03-29T20:00");
  auto who = interpreter.parse_slot({"who", SlotType::kContact, {}}, "to Bob please", context);
  REQUIRE(who);
  CHECK(who->value == "Bob");
  auto duration =
      interpreter.parse_slot({"d", SlotType::kDuration, {}}, "for half an hour", context);
  REQUIRE(duration);
  CHECK(duration->value == 1800);
  auto device =
      interpreter.parse_slot({"device", SlotType::kList, {"lamp", "fan"}}, "The lamp.", context);
  REQUIRE(device);
  CHECK(device->value == "lamp");
  auto text = interpreter.parse_slot(
      {"task", SlotType::kText, {}},
      "to water the plants on the balcony and then feed the cat twice", context);
  REQUIRE(text);  // answers may be longer than an utterance's text slot
  CHECK(text->value == "to water the plants on the balcony and then feed the cat twice");

  CHECK_FALSE(interpreter.parse_slot({"n", SlotType::kNumber, {}}, "banana", context));
  CHECK_FALSE(interpreter.parse_slot({"n", SlotType::kNumber, {}}, "", context));
  CHECK_FALSE(interpreter.parse_slot({"who", SlotType::kContact, {}}, "Zorro", context));
  CHECK_FALSE(interpreter.parse_slot({"device", SlotType::kList, {"lamp"}}, "the fan", context));
  CHECK_FALSE(interpreter.parse_slot({"when", SlotType::kDateTime, {}}, "whenever", context));
  CHECK_FALSE(interpreter.parse_slot({"d", SlotType::kDuration, {}}, "it is long", context));
}

TEST_CASE("matching: a text slot never holds only 'me', 'us' or 'you'") {
  Interpreter interpreter;
  interpreter.add({"finding",
                   "tell",
                   {"tell {name} {message}"},
                   {{"name", SlotType::kText, {}}, {"message", SlotType::kText, {}}}});
  Context context;
  // Asking Marvin, not asking it to pass a message on.
  CHECK_FALSE(interpreter.match_exact("tell me a joke", context));
  CHECK_FALSE(interpreter.match_exact("tell us the time", context));
  auto match = interpreter.match_exact("tell anna dinner is ready", context);
  REQUIRE(match);
  CHECK(match->slots.at("name").text == "anna");
  CHECK(match->slots.at("message").text == "dinner is ready");
}

TEST_CASE("voice changes: speak slower, louder, I can't hear you; not the radio, not walking") {
  using marvin::interpret::VoiceChange;
  using marvin::interpret::voice_change;
  const std::vector<std::pair<const char*, VoiceChange>> asked = {
      {"speak slower", VoiceChange::kSlower},
      {"Marvin, can you talk more slowly please?", VoiceChange::kSlower},
      {"slower", VoiceChange::kSlower},
      {"you are speaking too fast", VoiceChange::kSlower},
      {"not so fast", VoiceChange::kSlower},
      {"speak faster", VoiceChange::kFaster},
      {"you talk too slowly", VoiceChange::kFaster},
      {"louder please", VoiceChange::kLouder},
      {"speak up", VoiceChange::kLouder},
      {"could you speak a little louder", VoiceChange::kLouder},
      {"I can't hear you", VoiceChange::kLouder},
      {"I can hardly hear you", VoiceChange::kLouder},
      {"your voice is too quiet", VoiceChange::kLouder},
      {"speak more quietly", VoiceChange::kQuieter},
      {"you are too loud", VoiceChange::kQuieter},
  };
  for (const auto& [text, change] : asked) {
    const std::string said = text;
    CAPTURE(said);
    CHECK(voice_change(text) == change);
  }
  for (const char* text : {"turn the radio louder", "walk slower", "slow down", "speak to anna",
                           "what time is it", "louder and slower", "be quiet", "quiet",
                           "the music is too loud", "speak", "i can not hear the tv"}) {
    const std::string said = text;
    CAPTURE(said);
    CHECK_FALSE(voice_change(text).has_value());
  }
}
