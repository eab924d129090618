#include "interpret/tolerant_matcher.h"

#include <algorithm>

namespace marvin::interpret {
namespace {

constexpr int kTolerantStepBudget = 8000;

class TolerantRun {
 public:
  TolerantRun(const CompiledTemplate& compiled, const TolerantInput& input,
              const std::vector<std::string>& word_stems, const SynonymTable& synonyms,
              const SlotReader& reader)
      : program_(compiled.program),
        in_(input),
        word_stems_(word_stems),
        synonyms_(synonyms),
        reader_(reader) {}

  std::optional<TolerantMatch> best() {
    step(0, 0);
    return std::move(best_);
  }

 private:
  bool hopeless(float cost) const {
    return cost > TolerantCosts::kMaxCost || (best_ && cost > best_->cost) ||
           steps_ > kTolerantStepBudget;
  }

  // The cost of reading utterance word `pos` as template word `id`, or < 0 if it cannot.
  float word_cost(int id, std::size_t pos) const {
    if (in_.ids[pos] == id) return 0;
    const auto index = static_cast<std::size_t>(id);
    if (index < word_stems_.size() && word_stems_[index] == in_.stems[pos]) {
      return TolerantCosts::kStem;
    }
    auto it = synonyms_.find(in_.words[pos]);
    if (it != synonyms_.end() && std::find(it->second.begin(), it->second.end(), id) !=
                                     it->second.end()) {
      return TolerantCosts::kSynonym;
    }
    return -1;
  }

  void step(int pc, std::size_t pos) {
    ++steps_;
    if (hopeless(current_.cost)) return;
    const Instruction& in = program_[static_cast<std::size_t>(pc)];
    const std::size_t n = in_.words.size();
    switch (in.op) {
      case Instruction::Op::kWord: {
        if (pos < n) {
          float cost = word_cost(in.a, pos);
          if (cost >= 0) {
            with(cost, 1, [&] { step(pc + 1, pos + 1); });
          }
          with(TolerantCosts::kExtraWord, 0, [&] { step(pc, pos + 1); });
          // Two template words said the other way round: "what time it is".
          const Instruction& next = program_[static_cast<std::size_t>(pc) + 1];
          if (pos + 1 < n && next.op == Instruction::Op::kWord) {
            float first = word_cost(next.a, pos);
            float second = word_cost(in.a, pos + 1);
            if (first >= 0 && second >= 0) {
              with(TolerantCosts::kSwap + first + second, 2, [&] { step(pc + 2, pos + 2); });
            }
          }
        }
        // A template word is not missing when a slot took it ("help me find my slippers"
        // is not `find {what}` with "find" missing and what = the whole sentence).
        if (!in_a_slot(in.a)) {
          missing_.push_back(in.a);
          with(TolerantCosts::kMissingWord, 0, [&] { step(pc + 1, pos); });
          missing_.pop_back();
        }
        return;
      }
      case Instruction::Op::kJump:
        step(in.a, pos);
        return;
      case Instruction::Op::kSplit:
        step(in.a, pos);
        step(in.b, pos);
        return;
      case Instruction::Op::kSlot:
        slot(in.a, pc, pos);
        if (pos < n) with(TolerantCosts::kExtraWord, 0, [&] { step(pc, pos + 1); });
        with(TolerantCosts::kMissingSlot, 0, [&] { step(pc + 1, pos); });
        return;
      case Instruction::Op::kMatch: {
        float cost = current_.cost + TolerantCosts::kExtraWord * static_cast<float>(n - pos);
        if (cost > TolerantCosts::kMaxCost) return;
        // Ties go to more literal words, then to the more typed parse (fewer words in
        // free-text slots: "at 6:30 am" is a time, not a task), as in the exact matcher.
        std::size_t text_words = 0;
        for (std::size_t k = 0; k < spans_.size(); ++k) {
          if (reader_.is_text(current_.slots[k].slot)) text_words += spans_[k].second;
        }
        if (!best_ || cost < best_->cost ||
            (cost == best_->cost && (current_.literal_words > best_->literal_words ||
                                     (current_.literal_words == best_->literal_words &&
                                      text_words < best_text_words_)))) {
          best_ = current_;
          best_->cost = cost;
          best_text_words_ = text_words;
        }
        return;
      }
    }
  }

  template <typename Fn>
  void with(float cost, int literal, Fn&& fn) {
    current_.cost += cost;
    current_.literal_words += literal;
    fn();
    current_.cost -= cost;
    current_.literal_words -= literal;
  }

  void slot(int slot_index, int pc, std::size_t pos) {
    const std::size_t n = in_.words.size();
    const std::size_t longest = std::min(n - pos, reader_.max_words(slot_index));
    for (std::size_t length = 1; length <= longest; ++length) {
      if (hopeless(current_.cost)) return;
      // ... and a slot never takes a template word the parse counted as missing.
      if (is_missing(pos + length - 1)) return;
      const std::optional<SlotValue>& value = read(slot_index, pos, length);
      if (!value) continue;
      current_.slots.push_back({slot_index, *value});
      spans_.emplace_back(pos, length);
      step(pc + 1, pos + length);
      spans_.pop_back();
      current_.slots.pop_back();
    }
  }

  bool is_missing(std::size_t word) const {
    return std::any_of(missing_.begin(), missing_.end(),
                       [&](int id) { return word_cost(id, word) >= 0; });
  }

  bool in_a_slot(int id) const {
    for (const auto& [pos, length] : spans_) {
      for (std::size_t k = pos; k < pos + length; ++k) {
        if (word_cost(id, k) >= 0) return true;
      }
    }
    return false;
  }

  // Slot values are parsed once per (slot, start, length): backtracking tries the same
  // span on many paths, and a datetime parse is the costliest step here.
  const std::optional<SlotValue>& read(int slot_index, std::size_t pos, std::size_t length) {
    const std::size_t n = in_.words.size();
    const std::size_t key = (static_cast<std::size_t>(slot_index) * (n + 1) + pos) * (n + 1) + length;
    auto it = reads_.find(key);
    if (it == reads_.end()) {
      it = reads_.emplace(key, reader_.read(slot_index, in_.words.subspan(pos, length))).first;
    }
    return it->second;
  }

  std::unordered_map<std::size_t, std::optional<SlotValue>> reads_;
  const std::vector<Instruction>& program_;
  const TolerantInput& in_;
  const std::vector<std::string>& word_stems_;
  const SynonymTable& synonyms_;
  const SlotReader& reader_;
  TolerantMatch current_;
  std::vector<int> missing_;                                 // template words skipped so far
  std::vector<std::pair<std::size_t, std::size_t>> spans_;  // the slots' (start, length)
  std::optional<TolerantMatch> best_;
  std::size_t best_text_words_ = 0;
  int steps_ = 0;
};

}  // namespace

std::optional<TolerantMatch> match_tolerant(const CompiledTemplate& compiled,
                                            const TolerantInput& input,
                                            const std::vector<std::string>& word_stems,
                                            const SynonymTable& synonyms,
                                            const SlotReader& reader) {
  return TolerantRun(compiled, input, word_stems, synonyms, reader).best();
}

}  // namespace marvin::interpret
