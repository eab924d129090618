#include "interpret/matcher.h"

#include <algorithm>

namespace marvin::interpret {
namespace {

// Enough for any sensible template; a template needing more is cut off deterministically.
constexpr int kStepBudget = 20000;

class Run {
 public:
  Run(const CompiledTemplate& compiled, std::span<const std::string> words,
      std::span<const int> ids, const SlotReader& reader)
      : program_(compiled.program), words_(words), ids_(ids), reader_(reader) {}

  std::optional<TemplateMatch> best() {
    step(0, 0);
    return std::move(best_);
  }

 private:
  void step(int pc, std::size_t pos) {
    while (true) {
      if (++steps_ > kStepBudget) return;
      const Instruction& in = program_[static_cast<std::size_t>(pc)];
      switch (in.op) {
        case Instruction::Op::kWord:
          if (pos >= ids_.size() || ids_[pos] != in.a) return;
          ++pos;
          ++current_.literal_words;
          ++pc;
          continue;  // kSplit and slot() restore the counts when they backtrack

        case Instruction::Op::kJump:
          pc = in.a;
          continue;
        case Instruction::Op::kSplit: {
          const int saved_literal = current_.literal_words;
          const int saved_text = current_.text_words;
          const std::size_t saved_slots = current_.slots.size();
          step(in.a, pos);
          current_.literal_words = saved_literal;
          current_.text_words = saved_text;
          current_.slots.resize(saved_slots);
          pc = in.b;
          continue;
        }
        case Instruction::Op::kSlot:
          slot(in.a, pc, pos);
          return;
        case Instruction::Op::kMatch:
          if (pos == words_.size() && (!best_ || ranks_above(current_, *best_))) {
            best_ = current_;
          }
          return;
      }
    }
  }

  void slot(int slot_index, int pc, std::size_t pos) {
    const std::size_t remaining = words_.size() - pos;
    const std::size_t longest = std::min(remaining, reader_.max_words(slot_index));
    const Instruction& next = program_[static_cast<std::size_t>(pc) + 1];
    const bool text = reader_.is_text(slot_index);
    for (std::size_t length = 1; length <= longest; ++length) {
      std::size_t end = pos + length;
      // Cheap pruning: the word after the slot, or the end of the utterance, must fit.
      if (next.op == Instruction::Op::kWord && (end >= ids_.size() || ids_[end] != next.a)) {
        continue;
      }
      if (next.op == Instruction::Op::kMatch && end != words_.size()) continue;
      auto value = reader_.read(slot_index, words_.subspan(pos, length));
      if (!value) continue;
      int saved_literal = current_.literal_words;
      int saved_text = current_.text_words;
      current_.slots.push_back({slot_index, std::move(*value)});
      if (text) current_.text_words += static_cast<int>(length);
      step(pc + 1, end);
      current_.slots.pop_back();
      current_.literal_words = saved_literal;
      current_.text_words = saved_text;
      if (steps_ > kStepBudget) return;
    }
  }

  const std::vector<Instruction>& program_;
  std::span<const std::string> words_;
  std::span<const int> ids_;
  const SlotReader& reader_;
  TemplateMatch current_;
  std::optional<TemplateMatch> best_;
  int steps_ = 0;
};

}  // namespace

bool ranks_above(const TemplateMatch& a, const TemplateMatch& b) {
  if (a.literal_words != b.literal_words) return a.literal_words > b.literal_words;
  return a.text_words < b.text_words;
}

std::optional<TemplateMatch> match_template(const CompiledTemplate& compiled,
                                            std::span<const std::string> words,
                                            std::span<const int> word_ids,
                                            const SlotReader& reader) {
  if (words.size() < compiled.min_words || words.size() > compiled.max_words) {
    return std::nullopt;
  }
  return Run(compiled, words, word_ids, reader).best();
}

}  // namespace marvin::interpret
