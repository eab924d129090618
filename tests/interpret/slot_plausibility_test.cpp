// Entity slots (find {what}, tell {name} ..., turn on {device}) hold a person or a thing.
#include "interpret/slot_plausibility.h"

#include <doctest/doctest.h>

#include <string>
#include <vector>

#include "interpret/interpreter.h"
#include "interpret/normalizer.h"
#include "interpret/wordnet.h"

namespace mi = marvin::interpret;

namespace {

const mi::WordNet* plausibility_wordnet() {
  const mi::WordNet* w = mi::WordNet::installed();
  REQUIRE_MESSAGE(w != nullptr, "WordNet missing: apt-get install wordnet-base");
  return w;
}

bool entity(const char* text) {
  return mi::plausible_entity(mi::normalize(text), plausibility_wordnet());
}

mi::Context plausibility_context() {
  mi::Context context;
  context.now_utc_ms = 1795600000000;  // 2026-11-25T07:06:40Z
  context.time_zone = "Europe/Berlin";
  context.contact_names = {"Anna Schmidt", "Temperance Brennan"};
  return context;
}

mi::Interpreter finding_like() {
  mi::Interpreter interpreter;
  interpreter.add({"finder",
                   "find",
                   {"find {what}", "look for {what}", "where (is|are) {what}"},
                   {{"what", mi::SlotType::kText, {}}}});
  interpreter.add({"finder",
                   "tell",
                   {"tell {name} that {message}", "tell {name} {message}"},
                   {{"name", mi::SlotType::kText, {}}, {"message", mi::SlotType::kText, {}}}});
  interpreter.add(
      {"notes", "note", {"make a note (that|about) {text}"}, {{"text", mi::SlotType::kText, {}}}});
  return interpreter;
}

}  // namespace

TEST_CASE("entity slots are known by their names") {
  for (const char* name : {"what", "who", "name", "thing", "device", "room", "place"}) {
    const std::string slot_name = name;
    CAPTURE(slot_name);
    CHECK(mi::is_entity_slot(name));
  }
  for (const char* name : {"message", "task", "text", "when", "number"}) {
    const std::string slot_name = name;
    CAPTURE(slot_name);
    CHECK_FALSE(mi::is_entity_slot(name));
  }
}

TEST_CASE("a person or a thing in a home is plausible; information, qualities and events are not") {
  for (const char* text : {"my keys", "the remote", "my glasses case", "the kids", "anna", "bob",
                           "my medicine", "the living room lamp", "her", "the cat",
                           "the keys to the car", "my phone", "the ac", "dinner",
                           // names WordNet knows as abstract nouns
                           "mark", "felicity", "aunt grace"}) {
    const std::string said = text;
    CAPTURE(said);
    CHECK(entity(text));
  }
  for (const char* text :
       {"a recipe for pancakes", "advice on taxes", "the temperature it will be", "the weather",
        "some information", "the news", "the", "of the", "finalised yet", "ridiculous",
        "the nearest cash machine", "the best pizza place"}) {
    const std::string said = text;
    CAPTURE(said);
    CHECK_FALSE(entity(text));
  }
  CHECK(mi::only_function_words(mi::normalize("of the")));
  CHECK_FALSE(mi::only_function_words(mi::normalize("the door")));
}

TEST_CASE("a generic verb with an entity slot declines requests that name no thing or person") {
  const mi::Interpreter interpreter = finding_like();
  const mi::Context context = plausibility_context();
  // Out of scope, written for this test: each fits a template word for word.
  for (const char* text :
       {"find a recipe for banana bread", "look for advice on my taxes", "find the meaning of life",
        "tell the time it is in tokyo", "tell the news that matter today",
        "where is the nearest information", "find instructions for knitting a scarf"}) {
    const std::string said = text;
    CAPTURE(said);
    mi::Understanding u = interpreter.understand(text, context);
    const bool acted =
        u.outcome == mi::Understanding::Outcome::kMatch && u.match->skill_id == "finder";
    CHECK_FALSE(acted);
  }
  // In scope: people and things.
  auto intent_of = [&](const char* text) {
    mi::Understanding u = interpreter.understand(text, context);
    return u.outcome == mi::Understanding::Outcome::kMatch ? u.match->intent : std::string();
  };
  CHECK(intent_of("find my reading glasses") == "find");
  CHECK(intent_of("look for the tv remote") == "find");
  CHECK(intent_of("where are the scissors") == "find");
  CHECK(intent_of("tell anna that dinner is ready") == "tell");
  CHECK(intent_of("tell the kids dinner is ready") == "tell");
  // A contact is a person even when WordNet files the word under a quality.
  CHECK(intent_of("tell temperance that the tea is ready") == "tell");
  // Slots that are not entities keep taking any words.
  CHECK(intent_of("make a note about the weather") == "note");
  // Names WordNet files under abstract nouns are still people.
  CHECK(intent_of("tell mark that the tea is ready") == "tell");
}

TEST_CASE(
    "a question or clause is no name; strictly, bare abstract words are "
    "no name either") {
  for (const char* text : {"does cannabis", "why people get ill", "how to knit", "do the dishes",
                           "have you been", "are you ok", "is it raining", "am i"}) {
    const std::string said = text;
    CAPTURE(said);
    CHECK_FALSE(entity(text));
  }
  const mi::WordNet* wordnet = plausibility_wordnet();
  auto strictly = [&](const char* text) {
    return mi::plausible_entity(mi::normalize(text), wordnet, /*strict=*/true);
  };
  // The benefit of the doubt for one or two bare words is gone: "recipe" or
  // "mark" alone...
  CHECK(entity("recipe"));
  CHECK_FALSE(strictly("recipe"));
  CHECK_FALSE(strictly("mark"));
  // ...but things, people WordNet knows and words it does not know still pass.
  for (const char* text : {"my keys", "the doors", "martha", "the kids", "zorblat"}) {
    const std::string said = text;
    CAPTURE(said);
    CHECK(strictly(text));
  }
}

TEST_CASE(
    "examples of an intent that needs a thing do not make a loose fit "
    "act on a topic") {
  // Written for this test: examples teach the model that "find ..." and "where
  // ..." are this intent, so it is sure of it for any request that starts so.
  mi::Interpreter interpreter;
  interpreter.add({"finder",
                   "find",
                   {"find {what}", "look for {what}", "where (is|are) {what}"},
                   {{"what", mi::SlotType::kText, {}}},
                   {"find my keys", "please look for my glasses", "where did i leave my phone",
                    "can you find the cat", "help me look for my slippers", "where are the kids",
                    "search the house for my wallet", "have you found my purse", "find grandpa",
                    "where has my book gone"}});
  const mi::Context context = plausibility_context();
  for (const char* text :
       {"find out for me why people get the flu", "where does cannabis originate from"}) {
    const std::string said = text;
    CAPTURE(said);
    mi::Understanding u = interpreter.understand(text, context);
    CHECK(u.outcome != mi::Understanding::Outcome::kMatch);
    CHECK(u.reason == "names no person or thing for sure for find");
  }
  // A loose fit that names a contact or a thing still acts.
  for (const char* text : {"could you find anna schmidt for me please", "go and find my keys"}) {
    const std::string said = text;
    CAPTURE(said);
    mi::Understanding u = interpreter.understand(text, context);
    CAPTURE(u.reason);
    REQUIRE(u.outcome == mi::Understanding::Outcome::kMatch);
    CHECK(u.match->intent == "find");
  }
}

TEST_CASE("a device slot names a made thing: an appliance, a room, a name; not the world") {
  auto device = [](const char* text) {
    return mi::plausible_device(mi::normalize(text), plausibility_wordnet());
  };
  for (const char* yes : {"the porch light", "the heater", "the living room lamps", "the ac",
                          "the tv", "the vacuum", "the fan in the office", "everything", "it",
                          "the thermostat", "the garage door", "kitchen", "the zorbatron"}) {
    CAPTURE(std::string(yes));
    CHECK(device(yes));
  }
  for (const char* no :
       {"the sun", "the sea", "the friendliest breed", "the music", "the economy", "my mood"}) {
    CAPTURE(std::string(no));
    CHECK_FALSE(device(no));
  }
  CHECK(mi::is_device_slot("device"));
  CHECK_FALSE(mi::is_device_slot("what"));

  // Through the interpreter: the template fits word for word, the slot refuses the sun.
  mi::Interpreter home;
  home.add({"home",
            "query",
            {"what is the temperature of the {device}", "is [the] {device} on"},
            {{"device", mi::SlotType::kText, {}}}});
  const mi::Context context = plausibility_context();
  auto fridge = home.match_exact("what is the temperature of the fridge", context);
  REQUIRE(fridge);
  CHECK(fridge->slots.at("device").text == "fridge");
  CHECK_FALSE(home.match_exact("what is the temperature of the sun", context));
  CHECK_FALSE(home.match("what is the temperature of the sun", context));
}
