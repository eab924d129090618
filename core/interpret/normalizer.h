// Utterance (and template) text -> the word tokens the interpreter compares.
//
// Lower case (ASCII; other UTF-8 bytes are kept as they are), punctuation dropped, number
// words turned into digits ("Twenty-five" -> "25"), "8pm" split into "8 pm", "p.m." -> "pm",
// "7:30" and "2.5" kept as one token, curly apostrophes made straight ("what’s" -> "what's").
// Templates and utterances go through the same function, so they always agree.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace marvin::interpret {

std::vector<std::string> normalize(std::string_view text);

// Joins tokens with single spaces.
std::string join_words(const std::vector<std::string>& words, std::size_t begin,
                       std::size_t end);

}  // namespace marvin::interpret
