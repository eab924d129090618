#include "perception/command_grammar.h"

#include <algorithm>
#include <map>
#include <optional>
#include <set>

namespace marvin::perception {
namespace {

// ---- words ----------------------------------------------------------------------------

const char* const kOnes[] = {"zero", "one", "two", "three", "four", "five", "six", "seven",
                             "eight", "nine", "ten", "eleven", "twelve", "thirteen", "fourteen",
                             "fifteen", "sixteen", "seventeen", "eighteen", "nineteen"};
const char* const kTens[] = {"", "", "twenty", "thirty", "forty", "fifty", "sixty", "seventy",
                             "eighty", "ninety"};

void spell_number(unsigned long long n, std::vector<std::string>& out) {
  if (n >= 1000000) {  // read long digit strings digit by digit ("2024" stays a number below)
    for (char c : std::to_string(n)) out.emplace_back(kOnes[c - '0']);
    return;
  }
  if (n >= 1000) {
    spell_number(n / 1000, out);
    out.emplace_back("thousand");
    n %= 1000;
    if (n == 0) return;
  }
  if (n >= 100) {
    out.emplace_back(kOnes[n / 100]);
    out.emplace_back("hundred");
    n %= 100;
    if (n == 0) return;
  }
  if (n < 20) {
    out.emplace_back(kOnes[n]);
  } else {
    out.emplace_back(kTens[n / 10]);
    if (n % 10 != 0) out.emplace_back(kOnes[n % 10]);
  }
}

// ---- template syntax tree -------------------------------------------------------------

struct Node {
  enum Kind { kWord, kSlot, kSequence, kAlternatives, kOptional } kind = kSequence;
  std::string text;  // word or slot name
  std::vector<Node> items;
};

class TemplateParser {
 public:
  TemplateParser(std::string_view text, const std::string& where) : text_(text), where_(where) {}

  Node parse() {
    Node root = alternatives('\0');
    if (pos_ < text_.size()) fail("unexpected '" + std::string(1, text_[pos_]) + "'");
    return root;
  }

 private:
  [[noreturn]] void fail(const std::string& what) const {
    throw GrammarError(where_ + ", column " + std::to_string(pos_ + 1) + ": " + what);
  }

  Node alternatives(char close) {
    Node alt;
    alt.kind = Node::kAlternatives;
    alt.items.push_back(sequence(close));
    while (pos_ < text_.size() && text_[pos_] == '|') {
      ++pos_;
      alt.items.push_back(sequence(close));
    }
    if (close != '\0') {
      if (pos_ >= text_.size() || text_[pos_] != close) fail(std::string("missing '") + close + "'");
      ++pos_;
    }
    return alt;
  }

  Node sequence(char close) {
    Node seq;
    seq.kind = Node::kSequence;
    while (pos_ < text_.size()) {
      const char c = text_[pos_];
      if (c == '|' || (close != '\0' && c == close)) break;
      if (c == ')' || c == ']' || c == '}') fail(std::string("unbalanced '") + c + "'");
      if (c == ' ' || c == '\t') {
        ++pos_;
      } else if (c == '(') {
        ++pos_;
        seq.items.push_back(alternatives(')'));
      } else if (c == '[') {
        ++pos_;
        Node opt;
        opt.kind = Node::kOptional;
        opt.items.push_back(alternatives(']'));
        seq.items.push_back(std::move(opt));
      } else if (c == '{') {
        const std::size_t end = text_.find('}', pos_);
        if (end == std::string_view::npos) fail("missing '}'");
        Node slot;
        slot.kind = Node::kSlot;
        slot.text = std::string(text_.substr(pos_ + 1, end - pos_ - 1));
        if (slot.text.empty()) fail("empty slot name");
        pos_ = end + 1;
        seq.items.push_back(std::move(slot));
      } else {
        std::size_t end = pos_;
        while (end < text_.size() && std::string_view(" \t()[]{}|").find(text_[end]) == std::string_view::npos) ++end;
        for (std::string& word : grammar_words(text_.substr(pos_, end - pos_))) {
          Node w;
          w.kind = Node::kWord;
          w.text = std::move(word);
          seq.items.push_back(std::move(w));
        }
        pos_ = end;
      }
    }
    return seq;
  }

  std::string_view text_;
  std::string where_;
  std::size_t pos_ = 0;
};

// ---- rendering to JSGF ----------------------------------------------------------------

class Renderer {
 public:
  Renderer(const std::function<bool(std::string_view)>& known, std::vector<std::string>& skipped)
      : known_(known), skipped_(skipped) {}

  // Slot name -> JSGF rule reference ("<number>"), or "" when the slot has no usable words.
  std::map<std::string, std::string> slots;
  std::string where;

  // nullopt: cannot be said (an unknown word, an empty slot). "": says nothing.
  std::optional<std::string> render(const Node& node) {
    switch (node.kind) {
      case Node::kWord:
        if (known_ && !known_(node.text)) {
          skipped_.push_back("\"" + node.text + "\" is not in the dictionary (" + where + ")");
          return std::nullopt;
        }
        return node.text;
      case Node::kSlot: {
        auto it = slots.find(node.text);
        if (it == slots.end()) {
          throw GrammarError(where + ": slot {" + node.text + "} is not declared");
        }
        if (it->second.empty()) return std::nullopt;
        return it->second;
      }
      case Node::kOptional: {
        std::optional<std::string> inner = render(node.items.front());
        if (!inner || inner->empty()) return std::string();
        return "[" + strip_group(*inner) + "]";
      }
      case Node::kSequence: {
        std::string out;
        for (const Node& item : node.items) {
          std::optional<std::string> part = render(item);
          if (!part) return std::nullopt;
          if (part->empty()) continue;
          if (!out.empty()) out += ' ';
          out += *part;
        }
        return out;
      }
      case Node::kAlternatives: {
        std::vector<std::string> parts;
        bool can_be_empty = false;
        for (const Node& item : node.items) {
          std::optional<std::string> part = render(item);
          if (!part) continue;
          if (part->empty()) {
            can_be_empty = true;
          } else if (std::find(parts.begin(), parts.end(), *part) == parts.end()) {
            parts.push_back(*part);
          }
        }
        if (parts.empty()) {
          if (can_be_empty) return std::string();
          return std::nullopt;
        }
        std::string joined;
        for (const std::string& p : parts) joined += (joined.empty() ? "" : " | ") + p;
        if (can_be_empty) return "[" + joined + "]";
        if (parts.size() == 1) return joined;
        return "(" + joined + ")";
      }
    }
    return std::nullopt;
  }

 private:
  static std::string strip_group(const std::string& s) {
    if (s.size() >= 2 && s.front() == '(' && s.back() == ')') {
      int depth = 0;
      for (std::size_t i = 0; i < s.size(); ++i) {
        if (s[i] == '(') ++depth;
        if (s[i] == ')' && --depth == 0 && i + 1 != s.size()) return s;
      }
      return s.substr(1, s.size() - 2);
    }
    return s;
  }

  const std::function<bool(std::string_view)>& known_;
  std::vector<std::string>& skipped_;
};

// Built-in rules, written in the template syntax; `{x}` refers to the built-in rule x.
// Order matters: a rule may refer only to rules above it.
const std::pair<const char*, const char*> kBuiltinRules[] = {
    {"n_digit", "one|two|three|four|five|six|seven|eight|nine"},
    {"n_teen", "ten|eleven|twelve|thirteen|fourteen|fifteen|sixteen|seventeen|eighteen|nineteen"},
    {"n_tens", "twenty|thirty|forty|fifty|sixty|seventy|eighty|ninety"},
    {"n_below100", "{n_digit}|{n_teen}|{n_tens} [{n_digit}]"},
    {"number", "zero|{n_below100}|(a|{n_digit}) hundred [[and] {n_below100}]"},
    {"d_unit", "second|seconds|minute|minutes|hour|hours|day|days|week|weeks"},
    {"duration",
     "(a|an|{number}) {d_unit} [and (a half|{number} {d_unit})]|half an hour|"
     "a quarter of an hour"},
    {"t_hour",
     "{n_digit}|ten|eleven|twelve|thirteen|fourteen|fifteen|sixteen|seventeen|"
     "eighteen|nineteen|twenty [one|two|three]"},
    {"t_minute", "oh {n_digit}|{n_teen}|{n_tens} [{n_digit}]"},
    {"t_part", "am|pm|in the morning|in the afternoon|in the evening|at night"},
    {"time_of_day",
     "{t_hour} [{t_minute}] [o'clock] [{t_part}]|noon|midnight|half past {t_hour} [{t_part}]|"
     "[a] quarter (past|to) {t_hour} [{t_part}]|{n_below100} [minutes] (past|to) {t_hour}"},
    {"t_weekday", "monday|tuesday|wednesday|thursday|friday|saturday|sunday"},
    {"t_daypart", "morning|afternoon|evening|night"},
    {"t_day",
     "today|tonight|tomorrow [{t_daypart}]|the day after tomorrow|"
     "[on] [next] {t_weekday} [{t_daypart}]|this (morning|afternoon|evening)"},
    {"datetime",
     "[at] {time_of_day} [{t_day}]|{t_day} [at {time_of_day}]|in {duration}|"
     "every (day|morning|evening|night|weekday|{t_weekday}) [at {time_of_day}]|"
     "every {duration}|on weekdays [at {time_of_day}]"},
};

std::string rule_name(const std::string& text) {
  std::string out;
  for (char c : text) {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_';
    if (c >= 'A' && c <= 'Z') out += static_cast<char>(c - 'A' + 'a');
    else out += ok ? c : '_';
  }
  return out;
}

}  // namespace

std::vector<std::string> grammar_words(std::string_view text) {
  std::vector<std::string> words;
  std::string current;
  auto flush = [&] {
    // Apostrophes only inside words ("what's", "o'clock").
    while (!current.empty() && current.back() == '\'') current.pop_back();
    while (!current.empty() && current.front() == '\'') current.erase(current.begin());
    if (!current.empty()) words.push_back(current);
    current.clear();
  };
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c >= '0' && c <= '9') {
      flush();
      unsigned long long n = 0;
      std::size_t digits = 0;
      while (i < text.size() && text[i] >= '0' && text[i] <= '9') {
        if (digits++ < 18) n = n * 10 + static_cast<unsigned>(text[i] - '0');
        ++i;
      }
      --i;
      spell_number(n, words);
    } else if (c >= 'A' && c <= 'Z') {
      current += static_cast<char>(c - 'A' + 'a');
    } else if ((c >= 'a' && c <= 'z') || c == '\'' || static_cast<unsigned char>(c) >= 0x80) {
      current += c;
    } else {
      flush();
    }
  }
  flush();
  return words;
}

std::string GrammarOptions::default_polite_before() {
  return "[hey] [(could|can|would|will) you] [please]";
}

std::string GrammarOptions::default_polite_after() { return "[please] [thanks|thank you]"; }

std::vector<std::string> GrammarOptions::default_free_text_words() {
  // Everyday words for reminders and notes ("remind me to {task}"): errands, medicine,
  // meals, people, household objects. Extend through GrammarOptions.
  return {"a", "an", "the", "my", "your", "his", "her", "our", "their", "to", "and", "or",
          "of", "for", "with", "at", "in", "on", "up", "out", "off", "from", "about", "some",
          "this", "that", "it", "me", "him", "them", "us", "take", "give", "get", "buy",
          "bring", "call", "phone", "ring", "water", "feed", "walk", "clean", "wash", "cook",
          "make", "eat", "drink", "open", "close", "check", "pay", "send", "write", "read",
          "watch", "visit", "meet", "go", "put", "turn", "charge", "book", "order", "pick",
          "collect", "fetch", "pills", "pill", "medicine", "medication", "tablets", "drops",
          "insulin", "vitamins", "breakfast", "lunch", "dinner", "tea", "coffee", "milk",
          "bread", "food", "soup", "fruit", "plants", "flowers", "garden", "cat", "dog",
          "bird", "fish", "door", "window", "windows", "oven", "stove", "kettle", "heating",
          "lights", "bins", "bin", "rubbish", "laundry", "dishes", "bed", "shopping",
          "groceries", "doctor", "dentist", "nurse", "pharmacy", "appointment", "bills",
          "bill", "rent", "letter", "card", "present", "birthday", "mother", "father", "mom",
          "dad", "son", "daughter", "sister", "brother", "friend", "neighbour", "neighbor",
          "grandson", "granddaughter", "children", "phone", "glasses", "keys", "car", "bus",
          "train", "church", "exercise", "exercises", "stretch", "rest", "nap", "sleep",
          "shower", "bath", "teeth", "hair", "blood", "pressure", "sugar", "weight", "tv",
          "radio", "news", "book", "newspaper", "tickets", "post", "office", "bank", "shop",
          "market", "hospital", "appointment", "again", "today", "tomorrow", "morning",
          "evening", "night", "new", "old", "big", "small", "hot", "cold", "back", "home"};
}

GrammarResult build_command_grammar(std::span<const GrammarIntent> intents,
                                    const GrammarOptions& options,
                                    const std::function<bool(std::string_view)>& known_word) {
  GrammarResult result;
  std::string rules;
  std::vector<std::string> top;  // alternatives of the public rule
  Renderer renderer(known_word, result.skipped);

  auto render_text = [&](std::string_view text, const std::string& where) {
    renderer.where = where;
    return renderer.render(TemplateParser(text, where).parse());
  };

  // Built-in rules, each referring only to those above it.
  std::map<std::string, std::string> builtin_refs;
  for (const auto& [name, text] : kBuiltinRules) {
    renderer.slots = builtin_refs;
    std::optional<std::string> body = render_text(text, std::string("built-in rule <") + name + ">");
    builtin_refs[name] = body && !body->empty() ? "<" + std::string(name) + ">" : "";
    if (!builtin_refs[name].empty()) rules += "<" + std::string(name) + "> = " + *body + ";\n";
  }

  // Free text: every word the templates and phrases use plus the everyday list.
  std::set<std::string> free_words;
  auto add_free = [&](std::string_view text) {
    for (std::string& w : grammar_words(text)) {
      if (!known_word || known_word(w)) free_words.insert(std::move(w));
    }
  };
  for (const std::string& w : options.free_text_words) add_free(w);
  for (const GrammarIntent& intent : intents) {
    for (const std::string& t : intent.templates) {
      std::string plain;
      bool in_slot = false;
      for (char c : t) {
        if (c == '{') in_slot = true;
        plain += in_slot ? ' ' : c;
        if (c == '}') in_slot = false;
      }
      add_free(plain);
    }
    for (const GrammarSlot& slot : intent.slots) {
      for (const std::string& p : slot.phrases) add_free(p);
    }
  }
  std::string free_text_ref;
  if (!free_words.empty()) {
    std::string body;
    for (const std::string& w : free_words) body += (body.empty() ? "" : " | ") + w;
    rules += "<free_word> = " + body + ";\n<free_text> = <free_word>+;\n";
    free_text_ref = "<free_text>";
  }

  // One rule per intent, one rule per phrase slot.
  for (std::size_t i = 0; i < intents.size(); ++i) {
    const GrammarIntent& intent = intents[i];
    const std::string prefix = "i" + std::to_string(i) + "_" + rule_name(intent.name);
    std::map<std::string, std::string> slot_refs;
    for (const GrammarSlot& slot : intent.slots) {
      if (slot_refs.count(slot.name)) {
        throw GrammarError("intent " + intent.name + ": slot {" + slot.name + "} declared twice");
      }
      std::string ref;
      switch (slot.kind) {
        case SlotKind::kNumber: ref = builtin_refs["number"]; break;
        case SlotKind::kDuration: ref = builtin_refs["duration"]; break;
        case SlotKind::kDateTime: ref = builtin_refs["datetime"]; break;
        case SlotKind::kText: ref = free_text_ref; break;
        case SlotKind::kPhrases: {
          std::vector<std::string> phrases;
          for (const std::string& phrase : slot.phrases) {
            renderer.slots.clear();
            renderer.where = "intent " + intent.name + ", slot {" + slot.name + "} value \"" + phrase + "\"";
            std::vector<std::string> words = grammar_words(phrase);
            bool ok = !words.empty();
            for (const std::string& w : words) {
              if (known_word && !known_word(w)) {
                result.skipped.push_back("\"" + w + "\" is not in the dictionary (" + renderer.where + ")");
                ok = false;
              }
            }
            std::string joined;
            for (const std::string& w : words) joined += (joined.empty() ? "" : " ") + w;
            if (ok && std::find(phrases.begin(), phrases.end(), joined) == phrases.end()) {
              phrases.push_back(joined);
            }
          }
          if (!phrases.empty()) {
            ref = "<" + prefix + "_" + rule_name(slot.name) + ">";
            std::string body;
            for (const std::string& p : phrases) body += (body.empty() ? "" : " | ") + p;
            rules += ref + " = " + body + ";\n";
          }
          break;
        }
      }
      slot_refs[slot.name] = ref;
      if (options.accept_bare_slot_values && !ref.empty() && slot.kind != SlotKind::kText &&
          std::find(top.begin(), top.end(), ref) == top.end()) {
        top.push_back(ref);
      }
    }
    std::vector<std::string> bodies;
    for (std::size_t t = 0; t < intent.templates.size(); ++t) {
      renderer.slots = slot_refs;
      const std::string where = "intent " + intent.name + ", template " + std::to_string(t + 1) +
                                " \"" + intent.templates[t] + "\"";
      std::optional<std::string> body = render_text(intent.templates[t], where);
      if (!body || body->empty()) continue;
      bodies.push_back(*body);
      ++result.templates_used;
    }
    if (bodies.empty()) continue;
    std::string body;
    for (const std::string& b : bodies) body += (body.empty() ? "" : " | ") + b;
    rules += "<" + prefix + "> = " + body + ";\n";
    top.push_back("<" + prefix + ">");
  }
  // Politeness around the commands: one rule for all intents, wrapped once.
  auto polite = [&](const std::string& text, const char* what) -> std::string {
    if (text.empty()) return "";
    renderer.slots.clear();
    std::optional<std::string> body = render_text(text, std::string(what) + " \"" + text + "\"");
    return body ? *body : "";
  };
  const std::string before = polite(options.polite_before, "politeness before");
  const std::string after = polite(options.polite_after, "politeness after");
  if (!top.empty() && (!before.empty() || !after.empty())) {
    std::string commands;
    for (const std::string& t : top) commands += (commands.empty() ? "" : " | ") + t;
    rules += "<commands> = " + commands + ";\n";
    std::string wrapped = "<commands>";
    if (!before.empty()) {
      rules += "<polite_before> = " + before + ";\n";
      wrapped = "<polite_before> " + wrapped;
    }
    if (!after.empty()) {
      rules += "<polite_after> = " + after + ";\n";
      wrapped += " <polite_after>";
    }
    top = {wrapped};
  }

  std::vector<std::string> conversation;
  for (const std::string& phrase : options.conversation_phrases) {
    renderer.slots.clear();
    std::optional<std::string> body = render_text(phrase, "conversation phrase \"" + phrase + "\"");
    if (body && !body->empty()) conversation.push_back(*body);
  }
  if (!conversation.empty()) {
    std::string body;
    for (const std::string& b : conversation) body += (body.empty() ? "" : " | ") + b;
    rules += "<conversation> = " + body + ";\n";
    top.push_back("<conversation>");
  }
  if (result.templates_used == 0 && conversation.empty()) {
    throw GrammarError("the command grammar is empty: no template or phrase can be recognised");
  }
  std::string public_rule;
  for (const std::string& t : top) public_rule += (public_rule.empty() ? "" : " | ") + t;
  if (!options.optional_prefix.empty()) {
    renderer.slots.clear();
    std::optional<std::string> prefix =
        render_text(options.optional_prefix, "optional prefix \"" + options.optional_prefix + "\"");
    if (prefix && !prefix->empty()) public_rule = "[" + *prefix + "] (" + public_rule + ")";
  }
  result.jsgf = "#JSGF V1.0;\ngrammar marvin;\npublic <command> = " + public_rule + ";\n" + rules;
  return result;
}

}  // namespace marvin::perception
