// Utterance templates: the parser and the compiled form the matcher runs.
//
// Syntax (hassil / Rhasspy style): words; "(a|b c)" alternatives; "[a]" or "[a|b]" optional;
// "{name}" a slot. Groups nest. Literal words are normalised like utterances.
//
// The compiled form is a tiny backtracking program (as in regular-expression VMs): kWord
// matches one word id, kSlot one slot (several words), kSplit tries `a` then `b`, kJump
// continues at `a`, kMatch accepts if the utterance is used up. Word ids come from a
// Vocabulary shared by all templates so the matcher compares integers.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

namespace marvin::interpret {

class Vocabulary {
 public:
  static constexpr int kUnknown = -1;
  // The id of `word`, adding it if new.
  int intern(const std::string& word);
  // The id of `word`, or kUnknown.
  int find(const std::string& word) const;
  std::size_t size() const { return ids_.size(); }
  // Calls fn(word, id) for every word, in no particular order.
  template <typename Fn>
  void for_each(Fn&& fn) const {
    for (const auto& [word, id] : ids_) fn(word, id);
  }

 private:
  std::unordered_map<std::string, int> ids_;
};

struct Instruction {
  enum class Op { kWord, kSlot, kSplit, kJump, kMatch };
  Op op = Op::kMatch;
  int a = 0;  // kWord: word id; kSlot: slot index; kSplit/kJump: target
  int b = 0;  // kSplit: second target
};

struct CompiledTemplate {
  std::string source;                // as written by the skill
  std::vector<Instruction> program;  // ends with kMatch
  std::vector<int> required_words;   // word ids every matching utterance contains
  int literal_words_max = 0;         // upper bound of the rank this template can score
  std::size_t min_words = 0;         // utterance length bounds
  std::size_t max_words = 0;
};

// Where and why a template does not parse; `column` is 1-based.
struct TemplateSyntaxError {
  std::size_t column = 0;
  std::string message;
};

// Compiles `text`. `slot_names` are the declared slots (their index is the kSlot operand);
// `slot_max_words[i]` bounds how many words slot i may take. On a syntax error, an
// undeclared or repeated slot, or a template that could match nothing, returns false and
// fills `error`.
bool compile_template(std::string_view text, const std::vector<std::string>& slot_names,
                      const std::vector<std::size_t>& slot_max_words, Vocabulary& vocabulary,
                      CompiledTemplate& out, TemplateSyntaxError& error);

}  // namespace marvin::interpret
