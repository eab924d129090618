// What people add around a request: wake word, politeness and filler.
//
// strip_politeness() drops, at the start, "hey", "marvin", "ok", "so", "please", "could you [tell me]", "do you know",
// "can you [please]", "would you", "will you", "i need you to", "i want you to", "i would like
// you to", "go ahead and", "just", ..., and at the end "please", "for me", "thanks", "thank
// you", "marvin", repeatedly ("hey marvin, could you please ..."). Words are normalised
// (normalizer.h) first, so "what's" is already "what is". Never strips to nothing: a request
// made only of politeness ("thank you") is returned unchanged.
#pragma once

#include <string>
#include <vector>

namespace marvin::interpret {

std::vector<std::string> strip_politeness(const std::vector<std::string>& words);

// The Snowball (Porter 2) English stem of a normalised word; digits and tokens with ':' are
// returned unchanged. Thread-safe.
std::string stem(const std::string& word);

}  // namespace marvin::interpret
