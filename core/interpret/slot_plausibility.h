// What may fill a text slot that names a person or a thing ("find {what}", "tell {name} ...",
// "turn on [the] {device}"): a free-text slot otherwise swallows any words, so "find a recipe
// for hamburgers" or "tell the temperature it will tomorrow" would be acted on.
//
// A slot is such an *entity slot* by its name (the convention skill authors follow, documented
// in sdk/lua/README.md): what, who, name, thing, object, item, person, device, room, place.
// Its words must name something that could be in a home or someone:
//   - not only function words ("the", "a", "of", ...);
//   - not a question or clause ("does cannabis", "why people get ill", "how to ...");
//   - its head word (the last word before the first preposition or clause word, after
//     leading articles and possessives: "a recipe for hamburgers" -> "recipe") is a contact,
//     a pronoun, a word WordNet does not know (a name: "brexit", "bob") or a noun with at
//     least one of its first three senses outside the abstract categories (act, attribute,
//     cognition, communication, event, feeling, motive, phenomenon, process, relation,
//     shape, state, time): "keys", "the kids", "medicine" (an artifact in its 2nd sense) pass;
//     "recipe", "instructions", "temperature", "weather" do not;
//   - a head word WordNet knows only as a verb, adjective or adverb ("yet", "ridiculous") is
//     no entity.
// Without WordNet only the function-word rule applies.
#pragma once

#include <span>
#include <string>
#include <string_view>

namespace marvin::interpret {

class WordNet;

// True when a slot called `slot_name` holds a person or a thing (see above).
bool is_entity_slot(std::string_view slot_name);

// True when `words` may name a person or a thing. `wordnet` may be nullptr. `strict` drops
// the benefit of the doubt that one or two bare words are a name WordNet files under an
// abstract noun ("mark", "grace"): for a request that fits a template only loosely, where
// the words are more likely a topic ("find a recipe ..." -> "recipe").
bool plausible_entity(std::span<const std::string> words, const WordNet* wordnet,
                      bool strict = false);

// A slot called `device` names a made thing, not a thing in the world: its head word (or a
// word before it: "the vacuum cleaner") is a noun with an artifact sense (WordNet's
// noun.artifact) among its first four, a word WordNet does not know (a name: "aircon"), a
// reference ("it", "everything") or a household abbreviation ("ac", "tv"). So "the
// temperature of the sun" and "the friendliest breed" do not fill `the temperature of the
// {device}` or `what is [the] {device} doing`. Call after plausible_entity() holds.
bool is_device_slot(std::string_view slot_name);
bool plausible_device(std::span<const std::string> words, const WordNet* wordnet);

// True when every word is a function word ("the", "a", "of", "to", ...): never a slot value.
bool only_function_words(std::span<const std::string> words);

}  // namespace marvin::interpret
