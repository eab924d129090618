#include "interpret/template.h"

#include <algorithm>
#include <optional>
#include <set>

#include "interpret/normalizer.h"

namespace marvin::interpret {

int Vocabulary::intern(const std::string& word) {
  auto [it, added] = ids_.emplace(word, static_cast<int>(ids_.size()));
  return it->second;
}

int Vocabulary::find(const std::string& word) const {
  auto it = ids_.find(word);
  return it == ids_.end() ? kUnknown : it->second;
}

namespace {

struct Node {
  enum class Kind { kWord, kSlot, kSequence, kAlternative, kOptional };
  Kind kind = Kind::kSequence;
  std::string word;  // kWord
  int slot = -1;     // kSlot
  std::vector<Node> children;
};

struct ParseFailure {
  TemplateSyntaxError error;
};

class Parser {
 public:
  Parser(std::string_view text, const std::vector<std::string>& slot_names)
      : text_(text), slot_names_(slot_names) {}

  Node parse() {
    Node root = parse_sequence();
    if (at_ < text_.size()) {
      char c = text_[at_];
      if (c == '|') fail(at_, "'|' outside a group (write alternatives as \"(a|b)\")");
      fail(at_, std::string("unexpected '") + c + "' (nothing to close)");
    }
    return root;
  }

 private:
  [[noreturn]] void fail(std::size_t position, std::string message) {
    throw ParseFailure{{position + 1, std::move(message)}};
  }

  void flush_words(std::string& literal, Node& sequence) {
    for (std::string& word : normalize(literal)) {
      Node node;
      node.kind = Node::Kind::kWord;
      node.word = std::move(word);
      sequence.children.push_back(std::move(node));
    }
    literal.clear();
  }

  // Reads until '|', ')', ']', '}' or the end (not consumed).
  Node parse_sequence() {
    Node sequence;
    std::string literal;
    while (at_ < text_.size()) {
      char c = text_[at_];
      if (c == '|' || c == ')' || c == ']' || c == '}') break;
      if (c == '(' || c == '[') {
        flush_words(literal, sequence);
        sequence.children.push_back(parse_group());
      } else if (c == '{') {
        flush_words(literal, sequence);
        sequence.children.push_back(parse_slot());
      } else {
        literal.push_back(c);
        ++at_;
      }
    }
    flush_words(literal, sequence);
    return sequence;
  }

  Node parse_group() {
    std::size_t open = at_;
    char opener = text_[at_++];
    char closer = opener == '(' ? ')' : ']';
    Node alternative;
    alternative.kind = Node::Kind::kAlternative;
    while (true) {
      std::size_t branch_start = at_;
      Node branch = parse_sequence();
      if (branch.children.empty()) {
        fail(branch_start, opener == '('
                               ? "empty alternative in the group opened at column " +
                                     std::to_string(open + 1)
                               : "empty choice in the optional opened at column " +
                                     std::to_string(open + 1));
      }
      alternative.children.push_back(std::move(branch));
      if (at_ >= text_.size()) {
        fail(open, std::string("'") + opener + "' is never closed (expected '" + closer + "')");
      }
      char c = text_[at_];
      if (c == '|') {
        ++at_;
        continue;
      }
      if (c != closer) {
        fail(at_, std::string("unexpected '") + c + "' inside the group opened at column " +
                      std::to_string(open + 1) + " (expected '" + closer + "')");
      }
      ++at_;
      break;
    }
    if (opener == '(') return alternative;
    Node optional;
    optional.kind = Node::Kind::kOptional;
    optional.children.push_back(std::move(alternative));
    return optional;
  }

  Node parse_slot() {
    std::size_t open = at_++;
    std::size_t close = text_.find('}', at_);
    std::size_t other = text_.find_first_of("{()[]|", at_);
    if (close == std::string_view::npos || (other != std::string_view::npos && other < close)) {
      fail(open, "'{' is never closed (expected '}' after the slot name)");
    }
    std::string_view raw = text_.substr(at_, close - at_);
    std::size_t first = raw.find_first_not_of(' ');
    std::size_t last = raw.find_last_not_of(' ');
    if (first == std::string_view::npos) fail(open, "empty slot name in '{}'");
    std::string_view name = raw.substr(first, last - first + 1);
    for (std::size_t i = 0; i < name.size(); ++i) {
      char c = name[i];
      bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                c == '_';
      if (!ok) {
        fail(at_ + first + i, std::string("invalid character '") + c +
                                  "' in slot name (letters, digits and '_' only)");
      }
    }
    auto it = std::find(slot_names_.begin(), slot_names_.end(), name);
    if (it == slot_names_.end()) {
      fail(open, "slot {" + std::string(name) + "} is not declared in the intent's slots");
    }
    int index = static_cast<int>(it - slot_names_.begin());
    if (!used_slots_.insert(index).second) {
      fail(open, "slot {" + std::string(name) + "} is used twice in one template");
    }
    at_ = close + 1;
    Node node;
    node.kind = Node::Kind::kSlot;
    node.slot = index;
    return node;
  }

  std::string_view text_;
  const std::vector<std::string>& slot_names_;
  std::set<int> used_slots_;
  std::size_t at_ = 0;
};

struct Bounds {
  std::size_t min = 0;
  std::size_t max = 0;
  int literal_max = 0;
};

class Compiler {
 public:
  Compiler(const std::vector<std::size_t>& slot_max_words, Vocabulary& vocabulary,
           CompiledTemplate& out)
      : slot_max_words_(slot_max_words), vocabulary_(vocabulary), out_(out) {}

  Bounds compile(const Node& node, bool mandatory) {
    auto& program = out_.program;
    switch (node.kind) {
      case Node::Kind::kWord: {
        int id = vocabulary_.intern(node.word);
        program.push_back({Instruction::Op::kWord, id, 0});
        if (mandatory) out_.required_words.push_back(id);
        return {1, 1, 1};
      }
      case Node::Kind::kSlot:
        program.push_back({Instruction::Op::kSlot, node.slot, 0});
        return {1, slot_max_words_[static_cast<std::size_t>(node.slot)], 0};
      case Node::Kind::kSequence: {
        Bounds total;
        for (const Node& child : node.children) {
          Bounds b = compile(child, mandatory);
          total.min += b.min;
          total.max += b.max;
          total.literal_max += b.literal_max;
        }
        return total;
      }
      case Node::Kind::kAlternative: {
        if (node.children.size() == 1) return compile(node.children[0], mandatory);
        Bounds total{SIZE_MAX, 0, 0};
        std::vector<std::size_t> jumps;
        for (std::size_t i = 0; i < node.children.size(); ++i) {
          std::size_t split = program.size();
          bool last = i + 1 == node.children.size();
          if (!last) program.push_back({Instruction::Op::kSplit, static_cast<int>(split + 1), 0});
          Bounds b = compile(node.children[i], false);
          total.min = std::min(total.min, b.min);
          total.max = std::max(total.max, b.max);
          total.literal_max = std::max(total.literal_max, b.literal_max);
          if (!last) {
            jumps.push_back(program.size());
            program.push_back({Instruction::Op::kJump, 0, 0});
            program[split].b = static_cast<int>(program.size());
          }
        }
        for (std::size_t jump : jumps) program[jump].a = static_cast<int>(program.size());
        return total;
      }
      case Node::Kind::kOptional: {
        std::size_t split = program.size();
        program.push_back({Instruction::Op::kSplit, static_cast<int>(split + 1), 0});
        Bounds b = compile(node.children[0], false);
        program[split].b = static_cast<int>(program.size());
        return {0, b.max, b.literal_max};
      }
    }
    return {};
  }

 private:
  const std::vector<std::size_t>& slot_max_words_;
  Vocabulary& vocabulary_;
  CompiledTemplate& out_;
};

}  // namespace

bool compile_template(std::string_view text, const std::vector<std::string>& slot_names,
                      const std::vector<std::size_t>& slot_max_words, Vocabulary& vocabulary,
                      CompiledTemplate& out, TemplateSyntaxError& error) {
  Node root;
  try {
    root = Parser(text, slot_names).parse();
  } catch (const ParseFailure& failure) {
    error = failure.error;
    return false;
  }
  CompiledTemplate compiled;
  compiled.source = std::string(text);
  Bounds bounds = Compiler(slot_max_words, vocabulary, compiled).compile(root, true);
  if (bounds.min == 0) {
    error = {1, root.children.empty() ? "template is empty"
                                      : "template can match an empty utterance (everything "
                                        "in it is optional)"};
    return false;
  }
  compiled.program.push_back({Instruction::Op::kMatch, 0, 0});
  std::sort(compiled.required_words.begin(), compiled.required_words.end());
  compiled.required_words.erase(
      std::unique(compiled.required_words.begin(), compiled.required_words.end()),
      compiled.required_words.end());
  compiled.min_words = bounds.min;
  compiled.max_words = bounds.max;
  compiled.literal_words_max = bounds.literal_max;
  out = std::move(compiled);
  return true;
}

}  // namespace marvin::interpret
