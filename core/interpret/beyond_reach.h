// Requests Marvin declines, answered with the reason. Marvin works without the internet and
// has no music, news or messaging; a bare "Sorry, I don't know how to help with that" leaves
// the person asking again in other words, which cannot work either. The reason saves that,
// and where Marvin can do something close ("call Anna" for "text Anna") it says so.
//
// Only ever asked about an utterance the interpreter declined: it explains a refusal and
// never turns one into an action.
#pragma once

#include <optional>
#include <string>
#include <string_view>

namespace marvin::interpret {

// "Sorry, I can't tell you the weather: I work without the internet.", or nullopt when the
// utterance names none of the topics (weather, news, music, jokes, messages and e-mail, the
// internet, shopping, timetables and prices, following someone).
std::optional<std::string> beyond_reach(std::string_view utterance);

}  // namespace marvin::interpret
