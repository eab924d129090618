#include "telephony/callee.h"

#include <algorithm>
#include <cctype>
#include <cstring>

namespace marvin::telephony {
namespace {

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

// "my daughter" -> "daughter", "the doctor" -> "doctor", trimmed and lower case.
std::string bare(const std::string& text) {
  std::string s = lower(text);
  while (!s.empty() && s.front() == ' ') s.erase(0, 1);
  while (!s.empty() && s.back() == ' ') s.pop_back();
  for (const char* prefix : {"my ", "the ", "our "}) {
    if (s.rfind(prefix, 0) == 0) s.erase(0, std::string(prefix).size());
  }
  return s;
}

bool is_number(const std::string& s) {
  int digits = 0;
  for (char c : s) {
    if (std::isdigit(static_cast<unsigned char>(c))) {
      ++digits;
    } else if (!std::strchr(" +-/().", c)) {
      return false;
    }
  }
  return digits >= 3;
}

bool matches(const CallTarget& t, const std::string& who) {
  if (bare(t.name) == who || (!t.relation.empty() && bare(t.relation) == who)) return true;
  if (std::any_of(t.aliases.begin(), t.aliases.end(),
                  [&](const std::string& a) { return bare(a) == who; })) {
    return true;
  }
  const std::string first = bare(t.name.substr(0, t.name.find(' ')));
  return first == who;
}

}  // namespace

Callee resolve_callee(const std::string& who_heard, const std::vector<CallTarget>& contacts) {
  Callee out;
  const std::string who = bare(who_heard);
  if (who.empty()) {
    out.say = "Whom should I call?";
    return out;
  }
  if (is_number(who)) {
    out.kind = Callee::Kind::kNumber;
    out.number = who;
    out.say = "Call " + who + "?";
    return out;
  }
  std::vector<const CallTarget*> found;
  for (const CallTarget& t : contacts) {
    if (matches(t, who)) found.push_back(&t);
  }
  if (found.empty()) {
    out.say = "I don't know anyone called " + who_heard + ".";
    return out;
  }
  if (found.size() > 1) {
    out.kind = Callee::Kind::kAmbiguous;
    std::string list;
    for (std::size_t i = 0; i < found.size(); ++i) {
      out.candidates.push_back(found[i]->name);
      list += (i == 0 ? "" : i + 1 == found.size() ? " or " : ", ") + found[i]->name;
    }
    out.say = "Do you mean " + list + "?";
    return out;
  }
  out.target = *found.front();
  if (out.target.numbers.empty()) {
    out.kind = Callee::Kind::kNoNumber;
    out.say = "I have no number for " + out.target.name + ".";
    return out;
  }
  out.kind = Callee::Kind::kContact;
  out.number = out.target.numbers.front();
  out.say = "Call " + out.target.name + " on " + out.number + "?";
  return out;
}

}  // namespace marvin::telephony
