#include "interpret/number_words.h"

#include <array>
#include <charconv>
#include <utility>

namespace marvin::interpret {
namespace {

constexpr std::array<std::pair<std::string_view, int>, 28> kWords{{
    {"zero", 0},      {"one", 1},        {"two", 2},        {"three", 3},
    {"four", 4},      {"five", 5},       {"six", 6},        {"seven", 7},
    {"eight", 8},     {"nine", 9},       {"ten", 10},       {"eleven", 11},
    {"twelve", 12},   {"thirteen", 13},  {"fourteen", 14},  {"fifteen", 15},
    {"sixteen", 16},  {"seventeen", 17}, {"eighteen", 18},  {"nineteen", 19},
    {"twenty", 20},   {"thirty", 30},    {"forty", 40},     {"fifty", 50},
    {"sixty", 60},    {"seventy", 70},   {"eighty", 80},    {"ninety", 90},
}};

// Reads "below hundred": a unit/teen, or tens [unit]. Returns value and words used.
NumberRun read_below_hundred(std::span<const std::string> words) {
  if (words.empty()) return {};
  auto first = number_word_value(words[0]);
  if (!first) return {};
  if (*first >= 20 && words.size() > 1) {
    auto unit = number_word_value(words[1]);
    if (unit && *unit >= 1 && *unit <= 9) return {*first + *unit, 2};
  }
  return {*first, 1};
}

// Reads "below thousand": [below-hundred "hundred" [and] [below-hundred]] | below-hundred.
NumberRun read_below_thousand(std::span<const std::string> words) {
  NumberRun head = read_below_hundred(words);
  if (head.words == 0) return {};
  if (head.value >= 1 && head.value <= 9 && head.words < words.size() &&
      words[head.words] == "hundred") {
    NumberRun result{head.value * 100, head.words + 1};
    std::size_t at = result.words;
    bool has_and = at < words.size() && words[at] == "and";
    NumberRun tail = read_below_hundred(words.subspan(at + (has_and ? 1 : 0)));
    if (tail.words > 0 && tail.value > 0) {
      result.value += tail.value;
      result.words = at + (has_and ? 1 : 0) + tail.words;
    }
    return result;
  }
  return head;
}

}  // namespace

std::optional<std::int64_t> number_word_value(std::string_view word) {
  for (const auto& [name, value] : kWords) {
    if (name == word) return value;
  }
  return std::nullopt;
}

NumberRun read_number_words(std::span<const std::string> words) {
  // "hundred" / "thousand" alone after "a": "a hundred" is handled by callers; here a number
  // must start with a number word.
  NumberRun head = read_below_thousand(words);
  if (head.words == 0) return {};
  if (head.value >= 1 && head.words < words.size() && words[head.words] == "thousand") {
    NumberRun result{head.value * 1000, head.words + 1};
    std::size_t at = result.words;
    bool has_and = at < words.size() && words[at] == "and";
    NumberRun tail = read_below_thousand(words.subspan(at + (has_and ? 1 : 0)));
    if (tail.words > 0 && tail.value > 0) {
      result.value += tail.value;
      result.words = at + (has_and ? 1 : 0) + tail.words;
    }
    return result;
  }
  return head;
}

std::optional<double> parse_decimal(std::string_view token) {
  if (token.empty()) return std::nullopt;
  std::size_t dot = token.find('.');
  std::string_view whole = token.substr(0, dot);
  auto whole_value = parse_integer(whole);
  if (!whole_value) return std::nullopt;
  if (dot == std::string_view::npos) return static_cast<double>(*whole_value);
  std::string_view fraction = token.substr(dot + 1);
  if (fraction.empty() || fraction.size() > 9) return std::nullopt;
  auto fraction_value = parse_integer(fraction);
  if (!fraction_value) return std::nullopt;
  double scale = 1.0;
  for (std::size_t i = 0; i < fraction.size(); ++i) scale *= 10.0;
  return static_cast<double>(*whole_value) + static_cast<double>(*fraction_value) / scale;
}

std::optional<std::int64_t> parse_integer(std::string_view token) {
  if (token.empty() || token.size() > 15) return std::nullopt;
  for (char c : token) {
    if (c < '0' || c > '9') return std::nullopt;
  }
  std::int64_t value = 0;
  auto [end, error] = std::from_chars(token.data(), token.data() + token.size(), value);
  if (error != std::errc() || end != token.data() + token.size()) return std::nullopt;
  return value;
}

}  // namespace marvin::interpret
