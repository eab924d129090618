#include "interpret/phrasing.h"

#include <libstemmer.h>

#include <array>
#include <memory>
#include <string_view>

namespace marvin::interpret {
namespace {

// Leading phrases, longest first within each shared start (the first that fits is taken).
constexpr std::array<std::string_view, 45> kLeading{
    "can you tell me", "could you tell me", "would you tell me", "will you tell me",
    "do you know", "i want to know", "i would like to know", "i need to know", "let me know",
    "hey marvin", "ok marvin", "okay marvin", "hello marvin", "marvin",
    "could you please", "can you please", "would you please", "will you please",
    "could you kindly", "would you mind", "could you", "can you", "would you", "will you",
    "i need you to", "i want you to", "i would like you to", "i would love you to",
    "go ahead and", "please", "kindly", "just", "hey", "ok", "okay", "so", "um", "uh",
    "erm", "well", "oh", "excuse me", "sorry", "quickly", "now",
};
constexpr std::array<std::string_view, 9> kTrailing{
    "please", "for me please", "for me", "thank you", "thanks", "marvin", "now please",
    "if you can", "if you could",
};

std::size_t words_in(std::string_view phrase) {
  std::size_t n = 1;
  for (char c : phrase) n += c == ' ' ? 1U : 0U;
  return n;
}

bool phrase_at(const std::vector<std::string>& words, std::size_t at, std::size_t end,
               std::string_view phrase) {
  std::size_t i = at;
  std::size_t start = 0;
  while (start <= phrase.size()) {
    std::size_t space = phrase.find(' ', start);
    if (space == std::string_view::npos) space = phrase.size();
    if (i >= end || words[i] != phrase.substr(start, space - start)) return false;
    ++i;
    start = space + 1;
  }
  return true;
}

struct StemmerDeleter {
  void operator()(sb_stemmer* s) const { sb_stemmer_delete(s); }
};

}  // namespace

std::vector<std::string> strip_politeness(const std::vector<std::string>& words) {
  std::size_t begin = 0;
  std::size_t end = words.size();
  bool changed = true;
  while (changed) {
    changed = false;
    for (std::string_view phrase : kLeading) {
      std::size_t n = words_in(phrase);
      if (end - begin > n && phrase_at(words, begin, end, phrase)) {
        begin += n;
        changed = true;
        break;
      }
    }
    for (std::string_view phrase : kTrailing) {
      std::size_t n = words_in(phrase);
      if (end - begin > n && phrase_at(words, end - n, end, phrase)) {
        end -= n;
        changed = true;
        break;
      }
    }
  }
  return {words.begin() + static_cast<std::ptrdiff_t>(begin),
          words.begin() + static_cast<std::ptrdiff_t>(end)};
}

std::string stem(const std::string& word) {
  if (word.empty() || (word[0] >= '0' && word[0] <= '9')) return word;
  // A Snowball stemmer is not thread-safe; one per thread, created on first use.
  thread_local std::unique_ptr<sb_stemmer, StemmerDeleter> stemmer(
      sb_stemmer_new("english", "UTF_8"));
  if (!stemmer) return word;
  const sb_symbol* out = sb_stemmer_stem(
      stemmer.get(), reinterpret_cast<const sb_symbol*>(word.data()), static_cast<int>(word.size()));
  if (!out) return word;
  return std::string(reinterpret_cast<const char*>(out),
                     static_cast<std::size_t>(sb_stemmer_length(stemmer.get())));
}

}  // namespace marvin::interpret
