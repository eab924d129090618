#include "interpret/normalizer.h"

#include <span>

#include "interpret/number_words.h"

namespace marvin::interpret {
namespace {

bool is_digit(char c) { return c >= '0' && c <= '9'; }
bool is_alpha(char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z'); }
bool is_non_ascii(char c) { return (static_cast<unsigned char>(c) & 0x80U) != 0; }
bool is_word_char(char c) { return is_digit(c) || is_alpha(c) || is_non_ascii(c); }
char lower(char c) { return (c >= 'A' && c <= 'Z') ? static_cast<char>(c - 'A' + 'a') : c; }

bool is_ordinal_suffix(std::string_view s) {
  return s == "st" || s == "nd" || s == "rd" || s == "th";
}

// Splits "8pm" -> "8", "pm" and "20min" -> "20", "min", but keeps "21st" and "7:30".
void split_digit_letter(std::string token, std::vector<std::string>& out) {
  std::size_t i = 0;
  while (i < token.size() && (is_digit(token[i]) || token[i] == ':' || token[i] == '.')) ++i;
  if (i == 0 || i == token.size() || !is_digit(token[0]) || !is_alpha(token[i]) ||
      is_ordinal_suffix(std::string_view(token).substr(i))) {
    out.push_back(std::move(token));
    return;
  }
  out.push_back(token.substr(0, i));
  out.push_back(token.substr(i));
}

// Raw tokens: words, apostrophes inside words, ':' and '.' between digits.
std::vector<std::string> tokenize(std::string_view text) {
  std::string cleaned;
  cleaned.reserve(text.size());
  for (std::size_t i = 0; i < text.size(); ++i) {
    // U+2019 and U+2018 (curly quotes) become a straight apostrophe.
    if (i + 2 < text.size() && static_cast<unsigned char>(text[i]) == 0xE2 &&
        static_cast<unsigned char>(text[i + 1]) == 0x80 &&
        (static_cast<unsigned char>(text[i + 2]) == 0x99 ||
         static_cast<unsigned char>(text[i + 2]) == 0x98)) {
      cleaned.push_back('\'');
      i += 2;
      continue;
    }
    cleaned.push_back(lower(text[i]));
  }

  std::vector<std::string> out;
  std::string current;
  auto flush = [&] {
    while (!current.empty() && current.back() == '\'') current.pop_back();
    if (!current.empty()) split_digit_letter(std::move(current), out);
    current.clear();
  };
  const std::size_t n = cleaned.size();
  for (std::size_t i = 0; i < n; ++i) {
    char c = cleaned[i];
    char prev = i > 0 ? cleaned[i - 1] : ' ';
    char next = i + 1 < n ? cleaned[i + 1] : ' ';
    if (is_word_char(c)) {
      current.push_back(c);
    } else if (c == '\'' && !current.empty() && is_word_char(next)) {
      current.push_back(c);
    } else if ((c == ':' || c == '.') && is_digit(prev) && is_digit(next) && !current.empty()) {
      current.push_back(c);
    } else if (c == '.' && next == 'm' && !current.empty() &&
               (current.back() == 'a' || current.back() == 'p') &&
               (current.size() == 1 || is_digit(current[current.size() - 2]))) {
      // "a.m." / "p.m.": keep reading the same token.
    } else {
      flush();
    }
  }
  flush();
  return out;
}

}  // namespace

std::vector<std::string> normalize(std::string_view text) {
  std::vector<std::string> raw = tokenize(text);
  std::vector<std::string> out;
  out.reserve(raw.size());
  std::span<const std::string> all(raw);
  for (std::size_t i = 0; i < raw.size();) {
    NumberRun run = read_number_words(all.subspan(i));
    if (run.words > 0) {
      out.push_back(std::to_string(run.value));
      i += run.words;
    } else {
      out.push_back(std::move(raw[i]));
      ++i;
    }
  }
  return out;
}

std::string join_words(const std::vector<std::string>& words, std::size_t begin,
                       std::size_t end) {
  std::string out;
  for (std::size_t i = begin; i < end && i < words.size(); ++i) {
    if (!out.empty()) out.push_back(' ');
    out += words[i];
  }
  return out;
}

}  // namespace marvin::interpret
