// Small text helpers the built-in skills share for what they hear and say. Header-only, so
// each skill's shared library keeps its own copy and the skills stay independent of each
// other. ASCII only, like the interpreter's slots.
#pragma once

#include <cctype>
#include <cstdint>
#include <string>
#include <vector>

namespace marvin::builtin {

// "Turn On" -> "turn on".
inline std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

// The words of what someone said, in lower case; letters and apostrophes make a word:
// "Is it Sunday?" -> {"is", "it", "sunday"}, "I don't" -> {"i", "don't"}.
inline std::vector<std::string> words_in(const std::string& text) {
  std::vector<std::string> words;
  std::string word;
  for (char c : text + " ") {
    if (std::isalpha(static_cast<unsigned char>(c)) || c == '\'') {
      word += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    } else if (!word.empty()) {
      words.push_back(word);
      word.clear();
    }
  }
  return words;
}

// The answer to a yes/no question that lets a skill go ahead: "yes", "yeah, please",
// "sure", "OK", "please do", "go ahead". Anything else is no, and so is a yes with a no in
// it ("please don't", "yes, no, wait"): an unclear answer never removes, calls or enrols.
inline bool said_yes(const std::string& answer) {
  const std::vector<std::string> w = words_in(answer);
  if (w.empty()) return false;
  for (const std::string& x : w) {
    if (x == "no" || x == "not" || x == "don't" || x == "dont" || x == "nope" || x == "never" ||
        x == "wait") {
      return false;
    }
  }
  for (const char* yes : {"yes", "yeah", "yep", "yup", "sure", "ok", "okay", "please",
                          "certainly", "absolutely", "alright"}) {
    if (w[0] == yes) return true;
  }
  return w.size() > 1 && ((w[0] == "go" && w[1] == "ahead") || (w[0] == "do" && w[1] == "it"));
}

// {"the", "kitchen", "light"} -> "the kitchen light".
inline std::string join_words(const std::vector<std::string>& words) {
  std::string out;
  for (const std::string& w : words) out += (out.empty() ? "" : " ") + w;
  return out;
}

// "the kitchen light is on" -> "The kitchen light is on".
inline std::string capital(std::string s) {
  if (!s.empty()) s[0] = static_cast<char>(std::toupper(static_cast<unsigned char>(s[0])));
  return s;
}

// A name as the interpreter hands it (lower case) as it is written: "anna maria" ->
// "Anna Maria", "jean-luc" -> "Jean-Luc".
inline std::string capitalised(std::string s) {
  bool start = true;
  for (char& c : s) {
    if (start) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    start = c == ' ' || c == '-';
  }
  return s;
}

// {"Anna", "Ben", "Carl"} -> "Anna, Ben and Carl"; one part alone; none -> "".
inline std::string join_and(const std::vector<std::string>& parts) {
  std::string out;
  for (std::size_t i = 0; i < parts.size(); ++i) {
    if (i > 0) out += i + 1 == parts.size() ? " and " : ", ";
    out += parts[i];
  }
  return out;
}

// How long ago `ms` milliseconds is, said: "just now", "a minute ago", "20 minutes ago",
// "an hour ago", "5 hours ago".
inline std::string ago(std::int64_t ms) {
  const std::int64_t minutes = ms / 60000;
  if (minutes < 1) return "just now";
  if (minutes == 1) return "a minute ago";
  if (minutes < 60) return std::to_string(minutes) + " minutes ago";
  const std::int64_t hours = minutes / 60;
  return hours == 1 ? "an hour ago" : std::to_string(hours) + " hours ago";
}

}  // namespace marvin::builtin
