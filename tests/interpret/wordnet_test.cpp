// WordNet (Debian wordnet-base, listed in deps/debian-packages.txt) read in place, its synsets
// as features of the intent model, and the decisions that lean on a skill as a whole.
#include "interpret/wordnet.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "interpret/builtins.h"
#include "interpret/intent_model.h"
#include "interpret/interpreter.h"
#include "interpret/normalizer.h"

namespace mi = marvin::interpret;
using mi::Builtin;
using mi::Understanding;

namespace {

const mi::WordNet& wordnet() {
  const mi::WordNet* w = mi::WordNet::installed();
  // Debian's wordnet-base is a dependency (deps/debian-packages.txt); scripts/setup installs it.
  REQUIRE_MESSAGE(w != nullptr, "WordNet missing: apt-get install wordnet-base");
  return *w;
}

bool share_a_concept(const std::vector<std::string>& a, const std::vector<std::string>& b) {
  return std::any_of(a.begin(), a.end(), [&](const std::string& c) {
    return std::find(b.begin(), b.end(), c) != b.end();
  });
}

mi::Context wordnet_test_context() {
  mi::Context context;
  context.now_utc_ms = 1795600000000;  // 2026-11-25T07:06:40Z
  context.time_zone = "Europe/Berlin";
  return context;
}

}  // namespace

TEST_CASE("wordnet: synonyms share a concept, base forms and collocations are found") {
  const mi::WordNet& w = wordnet();
  CHECK(share_a_concept(w.concepts("recall", 3, 0), w.concepts("remember", 3, 0)));
  CHECK(share_a_concept(w.concepts("lamp", 3, 0), w.concepts("light", 3, 0)) == false);
  // Inflected forms reach their lemma: the same concepts.
  CHECK(w.concepts("reminders") == w.concepts("reminder"));
  CHECK(w.concepts("remembered") == w.concepts("remember"));
  // verb.exc: "went" is "go" (the verb; "go" is also a game and an adjective).
  const auto went = w.concepts("went");
  const auto go = w.concepts("go");
  CHECK_FALSE(went.empty());
  CHECK(std::all_of(went.begin(), went.end(), [&](const std::string& c) {
    return std::find(go.begin(), go.end(), c) != go.end();
  }));
  CHECK(w.knows("bear in mind"));
  CHECK_FALSE(w.concepts("bear in mind").empty());
  CHECK(w.concepts("qwzxv").empty());
  CHECK(w.concepts("").empty());
  // Hypernyms when asked for: "rescind" is a kind of {cancel, strike down}.
  CHECK(share_a_concept(w.concepts("rescind", 1, 1), w.concepts("cancel", 5, 0)));
  CHECK_FALSE(share_a_concept(w.concepts("rescind", 1, 0), w.concepts("cancel", 5, 0)));
  // Same database, same answer, in the same order.
  CHECK(w.concepts("alarm") == w.concepts("alarm"));
}

TEST_CASE("wordnet: a missing database is an error naming the file, not a crash") {
  std::string error;
  auto missing = mi::WordNet::open("/nonexistent/wordnet", error);
  CHECK(missing == nullptr);
  CHECK(error.find("/nonexistent/wordnet/index.noun: cannot open") == 0);
}

TEST_CASE("wordnet: a synonym no sentence used turns a miss into a hit") {
  // Two intents written without "recall"; WordNet knows it means "remember".
  std::vector<mi::LabelledSentence> sentences;
  for (const char* s : {"what do i have to remember", "things to remember", "remember this"}) {
    sentences.push_back({mi::normalize(s), 0});
  }
  for (const char* s : {"play some music", "play a song", "music please"}) {
    sentences.push_back({mi::normalize(s), 1});
  }
  mi::IntentModel plain = mi::IntentModel::train(sentences, 2);
  mi::IntentModel with_wordnet = mi::IntentModel::train(sentences, 2, &wordnet());
  const auto words = mi::normalize("recall");
  // Without WordNet the word is unknown: no preference beyond the classes' bias (0.49 when
  // written); with it, "recall" shares {remember, recall, ...} with "remember" (0.66).
  CHECK(plain.probabilities(words)[0] < 0.55F);
  CHECK(with_wordnet.probabilities(words)[0] > 0.6F);
  // Same sentences, same WordNet: the same model, bit for bit.
  mi::IntentModel again = mi::IntentModel::train(sentences, 2, &wordnet());
  CHECK(again.probabilities(words) == with_wordnet.probabilities(words));
}

TEST_CASE("dialogue answers in the person's own words: polarity, negation, typos") {
  struct Case {
    const char* text;
    Builtin expected;
  };
  // Written for this test.
  const Case cases[] = {
      {"i think that is accurate", Builtin::kYes},
      {"that answer is correct", Builtin::kYes},
      {"you are not wrong", Builtin::kYes},
      {"affirmitive", Builtin::kYes},  // one typo in a long word
      {"that is not accurate", Builtin::kNo},
      {"that is invalid", Builtin::kNo},
      {"incorect", Builtin::kNo},
      {"no good", Builtin::kNo},
      {"i would prefer not", Builtin::kNo},
      {"hey robot cancel that", Builtin::kStop},
      {"computer stop", Builtin::kStop},
      {"please repeat the question", Builtin::kRepeat},
      {"what?", Builtin::kRepeat},
      {"do not say anything else", Builtin::kStop},
      {"don't speak any more please", Builtin::kStop},
      {"do not forget the milk", Builtin::kNone},
      {"that is a negative", Builtin::kNo},
      {"thats not right", Builtin::kNo},  // typed without the apostrophe
      {"heck yes", Builtin::kYes},        // an intensifier before the answer
      {"oh god no", Builtin::kNo},
      {"hell cancel that", Builtin::kStop},
      // The robot on the move, told to stand (once "stop moving" was no request at all).
      {"stop moving", Builtin::kStop},
      {"marvin stop walking", Builtin::kStop},
      {"stop right there", Builtin::kStop},
      {"don't move", Builtin::kStop},
      {"stand still", Builtin::kStop},
      {"stay where you are", Builtin::kStop},
      {"stop the alarm", Builtin::kNone},
      {"do not move the chair", Builtin::kNone},
      // Questions and requests are never answers.
      {"is that true", Builtin::kNone},
      {"are you good", Builtin::kNone},
      {"is the answer correct", Builtin::kNone},
      {"that is true and false", Builtin::kNone},
      {"set a reminder that is correct", Builtin::kNone},
      {"repeat my shopping list", Builtin::kNone},
      {"good morning", Builtin::kNone},
  };
  for (const Case& c : cases) {
    CAPTURE(c.text);
    CHECK(mi::classify_builtin(c.text) == c.expected);
  }
}

TEST_CASE("one word WordNet files under stop or cancel stops; other verbs do not") {
  wordnet();
  mi::Interpreter in;
  mi::IntentSpec time{"clock", "time", {"what time is it"}, {}};
  in.add(time);
  for (const char* text : {"cease", "terminate", "rescind", "Discontinue!"}) {
    CAPTURE(text);
    CHECK(in.builtin(text) == Builtin::kStop);
  }
  for (const char* text :
       {"pause", "remove", "close", "play", "wait", "book", "rescind my order"}) {
    CAPTURE(text);
    CHECK(in.builtin(text) != Builtin::kStop);
  }
}

TEST_CASE("a skill that is clearly meant, with its intents close, is asked about") {
  mi::Interpreter in;
  mi::IntentSpec on{
      "lights", "on", {"turn on [the] {device}"}, {{"device", mi::SlotType::kText, {}}}};
  on.examples = {"turn on the lamp", "lamp on please", "switch the light on", "lights on",
                 "put the lamp on"};
  mi::IntentSpec off{
      "lights", "off", {"turn off [the] {device}"}, {{"device", mi::SlotType::kText, {}}}};
  off.examples = {"turn off the lamp", "lamp off please", "switch the light off", "lights off",
                  "put the lamp off"};
  in.add(on);
  in.add(off);
  mi::IntentSpec time{"clock", "time", {"what time is it"}, {}};
  time.examples = {"tell me the time", "what's the time", "how late is it"};
  in.add(time);
  const mi::Context context = wordnet_test_context();
  // "lamp" alone: the lights skill, but on or off?
  Understanding u = in.understand("lamp", context);
  CAPTURE(u.reason);
  REQUIRE(u.outcome == Understanding::Outcome::kAsk);
  CHECK(u.choices[0].skill_id == "lights");
  CHECK(u.choices[1].skill_id == "lights");
  CHECK(u.choices[0].intent != u.choices[1].intent);
  // Still exact where the words say it.
  Understanding exact = in.understand("turn off the lamp", context);
  REQUIRE(exact.outcome == Understanding::Outcome::kMatch);
  CHECK(exact.match->intent == "off");
  // Written for this test: questions shaped like the skills' sentences, none of them theirs.
  for (const char* text :
       {"is the museum open late", "how is paper made", "are the trains running on time",
        "what is the amount of salt in bread", "is the lamp shop open on sundays"}) {
    CAPTURE(text);
    CHECK(in.understand(text, context).outcome != Understanding::Outcome::kMatch);
  }
}
