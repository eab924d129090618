// WordNet (Princeton WordNet 3.0 as Debian's wordnet-base installs it in /usr/share/wordnet),
// read in place: the four index files and four data files are mapped into memory read-only,
// an index is searched by bisection over its line starts, and a synset is read at its byte
// offset in the data file (WordNet's synset ids are those offsets).
//
// What the interpreter takes from it: the *concepts* of a word, i.e. the synsets of its most
// frequent senses and their direct hypernyms, so that a word no skill wrote shares features
// with one it did ("rescind" -> its hypernym {cancel, strike down}; "recall" and "remember"
// share {remember, recall, ...}). Only the first few senses count: WordNet's rare senses are
// very broad (a "timer" is also a "clock", a "reminder" a "memento").
//
// Thread safety: a WordNet is immutable once opened; concepts() may be called from any
// number of threads at once.
#pragma once

#include <filesystem>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace marvin::interpret {

class WordNet {
 public:
  // Opens the database in `dir` (index.noun, data.noun, ... verb, adj, adv). nullptr and
  // `error` set ("/usr/share/wordnet/index.noun: cannot open: No such file ...") when a file is
  // missing or unreadable.
  static std::unique_ptr<WordNet> open(const std::filesystem::path& dir, std::string& error);

  // The installed database: $MARVIN_WORDNET_DIR if set, else /usr/share/wordnet. Opened on
  // first use and shared by the whole process; nullptr when missing, which is logged once
  // ("running without it") and is not an error: the interpreter then works without synonyms.
  static const WordNet* installed();

  ~WordNet();
  WordNet(const WordNet&) = delete;
  WordNet& operator=(const WordNet&) = delete;

  // Concept ids ("v02477334") for a lower-case word or collocation ("bear in mind"), in a fixed
  // order: for each part of speech (noun, verb, adjective) that knows the word, after WordNet's
  // base-form rules ("reminders" -> "reminder", "went" -> "go"), the synsets of its first
  // `senses` senses, then the direct hypernyms of its first `hypernym_senses` senses. Empty for
  // unknown words. Deterministic for the same database.
  std::vector<std::string> concepts(std::string_view word, int senses = 2,
                                    int hypernym_senses = 1) const;

  // concepts() of the verb only ("v..." ids), with the same rules.
  std::vector<std::string> verb_concepts(std::string_view word, int senses,
                                         int hypernym_senses) const;

  // True when `phrase` (words separated by spaces) is a lemma of some part of speech.
  bool knows(std::string_view phrase) const;

  // WordNet's lexicographer file numbers ("lexnames": 4 noun.act, 6 noun.artifact, 10
  // noun.communication, 18 noun.person, ...; see kNounAct ... below) of the first `senses`
  // noun senses of `word`, after the base-form rules ("recipes" -> "recipe"). Empty when the
  // word is no noun.
  std::vector<int> noun_categories(std::string_view word, int senses) const;

  // True when `word` (after base-form rules) is a verb or adjective lemma, or an adverb
  // (index.adv, when installed).
  bool is_verb_adjective_or_adverb(std::string_view word) const;

 private:
  struct Impl;
  std::vector<std::string> concepts_in(std::string_view word, int senses, int hypernym_senses,
                                       std::size_t first_part, std::size_t end_part) const;
  explicit WordNet(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace marvin::interpret
