#include "interpret/normalizer.h"

#include <array>
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

struct Rewrite {
  std::string_view from;
  std::string_view to;  // one or more words
};

// Contractions people type and say; expanded so "what's the time" and "what is the time" are
// the same words. Possessives ("mom's") are left alone: only these fixed forms change.
constexpr std::array kContractions{
    Rewrite{"what's", "what is"},   Rewrite{"whats", "what is"},     Rewrite{"it's", "it is"},
    Rewrite{"that's", "that is"},   Rewrite{"there's", "there is"},  Rewrite{"here's", "here is"},
    Rewrite{"who's", "who is"},     Rewrite{"where's", "where is"},  Rewrite{"when's", "when is"},
    Rewrite{"how's", "how is"},     Rewrite{"what're", "what are"},  Rewrite{"i'm", "i am"},
    Rewrite{"im", "i am"},          Rewrite{"i'd", "i would"},       Rewrite{"i'll", "i will"},
    Rewrite{"i've", "i have"},      Rewrite{"you're", "you are"},    Rewrite{"you'd", "you would"},
    Rewrite{"you'll", "you will"},  Rewrite{"you've", "you have"},   Rewrite{"we're", "we are"},
    Rewrite{"we'll", "we will"},    Rewrite{"they're", "they are"},  Rewrite{"let's", "let us"},
    Rewrite{"don't", "do not"},     Rewrite{"dont", "do not"},       Rewrite{"doesn't", "does not"},
    Rewrite{"didn't", "did not"},   Rewrite{"can't", "cannot"},      Rewrite{"cant", "cannot"},
    Rewrite{"won't", "will not"},   Rewrite{"isn't", "is not"},      Rewrite{"aren't", "are not"},
    Rewrite{"wasn't", "was not"},   Rewrite{"haven't", "have not"},  Rewrite{"hasn't", "has not"},
    Rewrite{"couldn't", "could not"}, Rewrite{"wouldn't", "would not"},
    Rewrite{"shouldn't", "should not"}, Rewrite{"wanna", "want to"}, Rewrite{"gonna", "going to"},
    Rewrite{"gotta", "got to"},     Rewrite{"gimme", "give me"},     Rewrite{"lemme", "let me"},
    Rewrite{"can not", "cannot"},
    // Typed without the apostrophe (words that are no other English word).
    Rewrite{"thats", "that is"},    Rewrite{"theres", "there is"},   Rewrite{"wheres", "where is"},
    Rewrite{"whos", "who is"},      Rewrite{"hows", "how is"},       Rewrite{"whens", "when is"},
    Rewrite{"doesnt", "does not"},  Rewrite{"didnt", "did not"},     Rewrite{"isnt", "is not"},
    Rewrite{"arent", "are not"},    Rewrite{"wasnt", "was not"},     Rewrite{"havent", "have not"},
    Rewrite{"hasnt", "has not"},    Rewrite{"couldnt", "could not"},
    Rewrite{"wouldnt", "would not"}, Rewrite{"shouldnt", "should not"},
    Rewrite{"youre", "you are"},    Rewrite{"ive", "i have"},        Rewrite{"theyre", "they are"},
};

// British spellings -> American, and a few common variants, so a template written either
// way matches both.
constexpr std::array kSpellings{
    Rewrite{"colour", "color"},           Rewrite{"colours", "colors"},
    Rewrite{"favourite", "favorite"},     Rewrite{"organise", "organize"},
    Rewrite{"organised", "organized"},    Rewrite{"centre", "center"},
    Rewrite{"programme", "program"},      Rewrite{"neighbour", "neighbor"},
    Rewrite{"cancelled", "canceled"},     Rewrite{"cancelling", "canceling"},
    Rewrite{"diarise", "diarize"},        Rewrite{"realise", "realize"},
    Rewrite{"recognise", "recognize"},    Rewrite{"apologise", "apologize"},
    Rewrite{"grey", "gray"},              Rewrite{"metre", "meter"},
    Rewrite{"litre", "liter"},            Rewrite{"theatre", "theater"},
    Rewrite{"travelling", "traveling"},   Rewrite{"labour", "labor"},
    Rewrite{"tonite", "tonight"},         Rewrite{"tmrw", "tomorrow"},
    Rewrite{"tmr", "tomorrow"},           Rewrite{"tomorow", "tomorrow"},
    Rewrite{"2morrow", "tomorrow"},       Rewrite{"pls", "please"},
    Rewrite{"plz", "please"},             Rewrite{"thx", "thanks"},
    Rewrite{"mins", "minutes"},           Rewrite{"min", "minutes"},
    Rewrite{"hrs", "hours"},              Rewrite{"hr", "hours"},
    Rewrite{"secs", "seconds"},           Rewrite{"sec", "seconds"},
    Rewrite{"o'clock", "o'clock"},        Rewrite{"oclock", "o'clock"},
    // Chat spellings people type.
    Rewrite{"ya", "you"},                 Rewrite{"u", "you"},
    Rewrite{"ur", "your"},                Rewrite{"doin", "doing"},
    Rewrite{"goin", "going"},             Rewrite{"wassup", "what is up"},
    Rewrite{"whassup", "what is up"},     Rewrite{"sup", "what is up"},
    Rewrite{"thanx", "thanks"},           Rewrite{"tho", "though"},
};

// Ordinal words -> "1st" style tokens ("the third" = "the 3rd").
constexpr std::array kOrdinals{
    Rewrite{"first", "1st"},      Rewrite{"second", "2nd"},      Rewrite{"third", "3rd"},
    Rewrite{"fourth", "4th"},     Rewrite{"fifth", "5th"},       Rewrite{"sixth", "6th"},
    Rewrite{"seventh", "7th"},    Rewrite{"eighth", "8th"},      Rewrite{"ninth", "9th"},
    Rewrite{"tenth", "10th"},     Rewrite{"eleventh", "11th"},   Rewrite{"twelfth", "12th"},
    Rewrite{"thirteenth", "13th"}, Rewrite{"fifteenth", "15th"}, Rewrite{"twentieth", "20th"},
    Rewrite{"thirtieth", "30th"},
};

template <std::size_t N>
const Rewrite* find_rewrite(const std::array<Rewrite, N>& table, std::string_view word) {
  for (const Rewrite& r : table) {
    if (r.from == word) return &r;
  }
  return nullptr;
}

void push_words(std::string_view text, std::vector<std::string>& out) {
  std::size_t at = 0;
  while (at < text.size()) {
    std::size_t space = text.find(' ', at);
    if (space == std::string_view::npos) space = text.size();
    out.emplace_back(text.substr(at, space - at));
    at = space + 1;
  }
}

// Contractions, spellings and ordinal words rewritten; "can not" joined first.
std::vector<std::string> rewrite_words(std::vector<std::string> raw) {
  std::vector<std::string> out;
  out.reserve(raw.size() + 4);
  for (std::size_t i = 0; i < raw.size(); ++i) {
    const std::string& word = raw[i];
    if (word == "can" && i + 1 < raw.size() && raw[i + 1] == "not") {
      out.emplace_back("cannot");
      ++i;
      continue;
    }
    const Rewrite* r = find_rewrite(kContractions, word);
    if (!r) r = find_rewrite(kSpellings, word);
    // "second" is also a unit of time ("wait a second"): only "the second" is an ordinal.
    if (!r && !(word == "second" && (out.empty() || out.back() != "the"))) {
      r = find_rewrite(kOrdinals, word);
    }
    if (r) {
      push_words(r->to, out);
    } else {
      out.push_back(word);
    }
  }
  return out;
}

}  // namespace

std::vector<std::string> normalize(std::string_view text) {
  std::vector<std::string> raw = rewrite_words(tokenize(text));
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
