#include "interpret/intent_table.h"

#include <map>
#include <unordered_map>
#include <utility>

namespace marvin::interpret {
namespace {

// Per template; beyond this the rest of its sentences are not compared (deterministic).
constexpr std::size_t kMaxSentencesPerTemplate = 2000;
// A list slot with more values than this is compared as a "{list}" placeholder.
constexpr std::size_t kMaxListExpansion = 32;

class Expander {
 public:
  Expander(const CompiledIntent& intent, const CompiledTemplate& compiled,
           const std::vector<std::string>& words_by_id)
      : intent_(intent), program_(compiled.program), words_by_id_(words_by_id) {}

  std::vector<std::string> sentences() {
    walk(0, "");
    return std::move(out_);
  }

 private:
  static std::string append(const std::string& sentence, const std::string& word) {
    return sentence.empty() ? word : sentence + " " + word;
  }

  void walk(int pc, std::string sentence) {
    while (out_.size() < kMaxSentencesPerTemplate) {
      const Instruction& in = program_[static_cast<std::size_t>(pc)];
      switch (in.op) {
        case Instruction::Op::kWord:
          sentence = append(sentence, words_by_id_[static_cast<std::size_t>(in.a)]);
          ++pc;
          continue;
        case Instruction::Op::kJump:
          pc = in.a;
          continue;
        case Instruction::Op::kSplit:
          walk(in.a, sentence);
          pc = in.b;
          continue;
        case Instruction::Op::kSlot: {
          const PreparedSlot& slot = intent_.slots[static_cast<std::size_t>(in.a)];
          if (slot.spec.type == SlotType::kList && slot.list_words.size() <= kMaxListExpansion) {
            for (const auto& value : slot.list_words) {
              std::string with = sentence;
              for (const std::string& word : value) with = append(with, word);
              walk(pc + 1, with);
            }
            return;
          }
          sentence = append(sentence, std::string("{") + to_string(slot.spec.type) + "}");
          ++pc;
          continue;
        }
        case Instruction::Op::kMatch:
          out_.push_back(std::move(sentence));
          return;
      }
    }
  }

  const CompiledIntent& intent_;
  const std::vector<Instruction>& program_;
  const std::vector<std::string>& words_by_id_;
  std::vector<std::string> out_;
};

std::string describe(const CompiledIntent& intent) {
  return "skill \"" + intent.spec.skill_id + "\" (intent " + intent.spec.intent + ")";
}

}  // namespace

std::vector<std::string> find_conflicts(const std::vector<CompiledIntent>& intents,
                                        const Vocabulary& vocabulary) {
  std::vector<std::string> words_by_id(vocabulary.size());
  vocabulary.for_each([&](const std::string& word, int id) {
    words_by_id[static_cast<std::size_t>(id)] = word;
  });

  std::unordered_map<std::string, std::size_t> first_claim;  // sentence -> intent index
  // (earlier intent, later intent) -> first sentence and count; ordered for stable output.
  std::map<std::pair<std::size_t, std::size_t>, std::pair<std::string, std::size_t>> clashes;
  for (std::size_t i = 0; i < intents.size(); ++i) {
    for (const CompiledTemplate& compiled : intents[i].templates) {
      for (std::string& sentence : Expander(intents[i], compiled, words_by_id).sentences()) {
        auto [it, added] = first_claim.emplace(sentence, i);
        if (added) continue;
        std::size_t earlier = it->second;
        if (intents[earlier].spec.skill_id == intents[i].spec.skill_id) continue;
        auto& clash = clashes[{earlier, i}];
        if (clash.second++ == 0) clash.first = std::move(sentence);
      }
    }
  }

  std::vector<std::string> out;
  for (const auto& [pair, clash] : clashes) {
    std::string line = "\"" + clash.first + "\" is claimed by " + describe(intents[pair.first]) +
                       " and " + describe(intents[pair.second]);
    if (clash.second > 1) {
      line += " (and " + std::to_string(clash.second - 1) + " more sentence" +
              (clash.second > 2 ? "s" : "") + ")";
    }
    out.push_back(std::move(line));
  }
  return out;
}

}  // namespace marvin::interpret
