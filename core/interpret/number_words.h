// English number words -> values: "eight" -> 8, "twenty five" -> 25,
// "one hundred and five" -> 105, "two thousand twenty" -> 2020.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>

namespace marvin::interpret {

// Value of a single number word ("zero".."nineteen", "twenty".."ninety"), or nullopt.
std::optional<std::int64_t> number_word_value(std::string_view word);

struct NumberRun {
  std::int64_t value = 0;
  std::size_t words = 0;  // how many tokens the number spans (0 = no number here)
};

// The longest number spelled in words starting at words[0]. Digits are not accepted here
// (the normaliser has turned words into digits before anything else looks at numbers).
// Rules: tens + unit ("twenty five"), "X hundred [and] Y", "X thousand [and] Y". Two units
// in a row are two numbers ("eight thirty" = 8, then 30), so clock times stay readable.
NumberRun read_number_words(std::span<const std::string> words);

// Parses a token of digits with an optional decimal part ("25", "2.5"); nullopt otherwise.
std::optional<double> parse_decimal(std::string_view token);

// Parses a token of digits only ("25"); nullopt otherwise or when out of range.
std::optional<std::int64_t> parse_integer(std::string_view token);

}  // namespace marvin::interpret
