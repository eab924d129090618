#include "interpret/wordnet.h"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <optional>

#include "common/log.h"

namespace marvin::interpret {
namespace {

// A file mapped read-only (empty view for an empty file).
class MappedFile {
 public:
  MappedFile() = default;
  MappedFile(const MappedFile&) = delete;
  MappedFile& operator=(const MappedFile&) = delete;
  ~MappedFile() {
    if (data_ != nullptr) munmap(data_, size_);
  }

  bool open(const std::filesystem::path& path, std::string& error) {
    int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) {
      error = path.string() + ": cannot open: " + std::strerror(errno);
      return false;
    }
    struct stat st {};
    if (fstat(fd, &st) != 0) {
      error = path.string() + ": cannot stat: " + std::strerror(errno);
      ::close(fd);
      return false;
    }
    size_ = static_cast<std::size_t>(st.st_size);
    if (size_ > 0) {
      void* p = mmap(nullptr, size_, PROT_READ, MAP_PRIVATE, fd, 0);
      if (p == MAP_FAILED) {
        error = path.string() + ": cannot map: " + std::strerror(errno);
        ::close(fd);
        size_ = 0;
        return false;
      }
      data_ = p;
    }
    ::close(fd);
    return true;
  }
  std::string_view view() const {
    return data_ == nullptr ? std::string_view()
                            : std::string_view(static_cast<const char*>(data_), size_);
  }

 private:
  void* data_ = nullptr;
  std::size_t size_ = 0;
};

// A sorted file of lines `key rest...` (an index or an exception list), searched by key.
class SortedLines {
 public:
  bool open(const std::filesystem::path& path, std::string& error) {
    if (!file_.open(path, error)) return false;
    std::string_view text = file_.view();
    std::size_t at = 0;
    while (at < text.size()) {
      std::size_t end = text.find('\n', at);
      if (end == std::string_view::npos) end = text.size();
      // The licence at the top of an index starts with two spaces.
      if (end > at && text[at] != ' ') starts_.push_back(static_cast<std::uint32_t>(at));
      at = end + 1;
    }
    return true;
  }

  // The line whose first field is `key`, without its newline, or nullopt.
  std::optional<std::string_view> find(std::string_view key) const {
    std::string_view text = file_.view();
    std::size_t lo = 0, hi = starts_.size();
    while (lo < hi) {
      std::size_t mid = lo + (hi - lo) / 2;
      std::string_view line = line_at(text, starts_[mid]);
      std::string_view first = line.substr(0, line.find(' '));
      int c = first.compare(key);
      if (c == 0) return line;
      if (c < 0) {
        lo = mid + 1;
      } else {
        hi = mid;
      }
    }
    return std::nullopt;
  }

 private:
  static std::string_view line_at(std::string_view text, std::uint32_t start) {
    std::size_t end = text.find('\n', start);
    if (end == std::string_view::npos) end = text.size();
    return text.substr(start, end - start);
  }

  MappedFile file_;
  std::vector<std::uint32_t> starts_;
};

std::vector<std::string_view> fields(std::string_view line) {
  std::vector<std::string_view> out;
  std::size_t at = 0;
  while (at < line.size()) {
    std::size_t end = line.find(' ', at);
    if (end == std::string_view::npos) end = line.size();
    if (end > at) out.push_back(line.substr(at, end - at));
    at = end + 1;
  }
  return out;
}

std::size_t to_number(std::string_view s, int base) {
  std::size_t n = 0;
  for (char c : s) {
    int digit = -1;
    if (c >= '0' && c <= '9') digit = c - '0';
    if (base == 16 && c >= 'a' && c <= 'f') digit = c - 'a' + 10;
    if (digit < 0 || digit >= base) return 0;
    n = n * static_cast<std::size_t>(base) + static_cast<std::size_t>(digit);
  }
  return n;
}

struct Part {
  const char* name;  // file suffix
  char letter;       // concept id prefix
};
constexpr std::array<Part, 3> kParts{{{"noun", 'n'}, {"verb", 'v'}, {"adj", 'a'}}};

// WordNet's detachment rules ("morphy"): suffix -> replacement, per part of speech.
constexpr std::array<std::array<std::pair<std::string_view, std::string_view>, 8>, 3> kRules{{
    {{{"ses", "s"},
      {"xes", "x"},
      {"zes", "z"},
      {"ches", "ch"},
      {"shes", "sh"},
      {"men", "man"},
      {"ies", "y"},
      {"s", ""}}},
    {{{"ies", "y"},
      {"es", "e"},
      {"es", ""},
      {"ed", "e"},
      {"ed", ""},
      {"ing", "e"},
      {"ing", ""},
      {"s", ""}}},
    {{{"est", "e"}, {"est", ""}, {"er", "e"}, {"er", ""}, {"", ""}, {"", ""}, {"", ""}, {"", ""}}},
}};

}  // namespace

struct WordNet::Impl {
  std::array<SortedLines, 3> index;
  std::array<SortedLines, 3> exceptions;
  std::array<MappedFile, 3> data;
  SortedLines adverbs;  // index.adv: only asked whether a word is an adverb

  // The index line of `lemma` (underscores for spaces) in part `p`, after base-form rules.
  std::optional<std::string_view> lookup(std::size_t p, const std::string& lemma) const {
    if (auto line = index[p].find(lemma)) return line;
    // Collocations are looked up as said: most word pairs are none, and this is the hot path.
    if (lemma.find('_') != std::string::npos) return std::nullopt;
    if (auto exc = exceptions[p].find(lemma)) {
      std::vector<std::string_view> f = fields(*exc);
      for (std::size_t i = 1; i < f.size(); ++i) {
        if (auto line = index[p].find(f[i])) return line;
      }
    }
    for (const auto& [suffix, replacement] : kRules[p]) {
      if (suffix.empty() || lemma.size() <= suffix.size() + 1 || !lemma.ends_with(suffix)) {
        continue;
      }
      std::string base = lemma.substr(0, lemma.size() - suffix.size()) + std::string(replacement);
      if (auto line = index[p].find(base)) return line;
    }
    return std::nullopt;
  }

  // Direct hypernyms of the synset at `offset` in part `p`.
  std::vector<std::string> hypernyms(std::size_t p, std::size_t offset) const {
    std::vector<std::string> out;
    std::string_view text = data[p].view();
    if (offset >= text.size()) return out;
    std::size_t end = text.find('\n', offset);
    std::string_view line =
        text.substr(offset, (end == std::string_view::npos ? text.size() : end) - offset);
    line = line.substr(0, line.find(" | "));
    std::vector<std::string_view> f = fields(line);
    // offset lex_filenum ss_type w_cnt(hex) [word lex_id]... p_cnt [symbol offset pos src/tgt]...
    if (f.size() < 4) return out;
    std::size_t words = to_number(f[3], 16);
    std::size_t at = 4 + 2 * words;
    if (at >= f.size()) return out;
    std::size_t pointers = to_number(f[at], 10);
    ++at;
    for (std::size_t k = 0; k < pointers && at + 3 < f.size() + 0; ++k, at += 4) {
      if (f[at] == "@" || f[at] == "@i") {
        char letter = f[at + 2].empty() ? 'n' : f[at + 2][0];
        out.push_back(std::string(1, letter == 's' ? 'a' : letter) + std::string(f[at + 1]));
      }
    }
    return out;
  }
};

WordNet::WordNet(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
WordNet::~WordNet() = default;

std::unique_ptr<WordNet> WordNet::open(const std::filesystem::path& dir, std::string& error) {
  auto impl = std::make_unique<Impl>();
  for (std::size_t p = 0; p < kParts.size(); ++p) {
    const std::string name = kParts[p].name;
    if (!impl->index[p].open(dir / ("index." + name), error)) return nullptr;
    if (!impl->data[p].open(dir / ("data." + name), error)) return nullptr;
    // Exception lists are optional (older packages ship them, some do not).
    std::string ignored;
    impl->exceptions[p].open(dir / (name + ".exc"), ignored);
  }
  std::string ignored;
  impl->adverbs.open(dir / "index.adv", ignored);
  return std::unique_ptr<WordNet>(new WordNet(std::move(impl)));
}

const WordNet* WordNet::installed() {
  static const std::unique_ptr<WordNet> instance = [] {
    const char* env = std::getenv("MARVIN_WORDNET_DIR");
    std::filesystem::path dir = env != nullptr && *env != '\0' ? env : "/usr/share/wordnet";
    std::string error;
    auto wordnet = open(dir, error);
    if (!wordnet) {
      log(LogLevel::kWarning, "interpret",
          "WordNet not found (" + error +
              "); understanding requests without its synonyms (install Debian's wordnet-base)");
    }
    return wordnet;
  }();
  return instance.get();
}

bool WordNet::knows(std::string_view phrase) const {
  std::string lemma(phrase);
  for (char& c : lemma) c = c == ' ' ? '_' : c;
  for (std::size_t p = 0; p < kParts.size(); ++p) {
    if (impl_->index[p].find(lemma)) return true;
  }
  return false;
}

std::vector<int> WordNet::noun_categories(std::string_view word, int senses) const {
  std::vector<int> out;
  if (word.empty() || word.find(' ') != std::string_view::npos) return out;
  auto line = impl_->lookup(0, std::string(word));
  if (!line) return out;
  std::vector<std::string_view> f = fields(*line);
  if (f.size() < 4) return out;
  std::size_t synsets = to_number(f[2], 10);
  std::size_t at = 4 + to_number(f[3], 10) + 2;
  std::string_view text = impl_->data[0].view();
  for (std::size_t k = 0; k < synsets && at + k < f.size() && static_cast<int>(k) < senses;
       ++k) {
    // A synset line starts `offset lex_filenum ...`.
    std::size_t offset = to_number(f[at + k], 10);
    if (offset >= text.size()) continue;
    std::size_t end = text.find('\n', offset);
    std::vector<std::string_view> synset = fields(
        text.substr(offset, (end == std::string_view::npos ? text.size() : end) - offset));
    if (synset.size() > 1) out.push_back(static_cast<int>(to_number(synset[1], 10)));
  }
  return out;
}

bool WordNet::is_verb_adjective_or_adverb(std::string_view word) const {
  if (word.empty()) return false;
  const std::string lemma(word);
  return impl_->lookup(1, lemma).has_value() || impl_->lookup(2, lemma).has_value() ||
         impl_->adverbs.find(lemma).has_value();
}

std::vector<std::string> WordNet::concepts(std::string_view word, int senses,
                                           int hypernym_senses) const {
  return concepts_in(word, senses, hypernym_senses, 0, kParts.size());
}

std::vector<std::string> WordNet::verb_concepts(std::string_view word, int senses,
                                                int hypernym_senses) const {
  return concepts_in(word, senses, hypernym_senses, 1, 2);
}

std::vector<std::string> WordNet::concepts_in(std::string_view word, int senses,
                                              int hypernym_senses, std::size_t first_part,
                                              std::size_t end_part) const {
  std::vector<std::string> out;
  if (word.empty()) return out;
  std::string lemma(word);
  for (char& c : lemma) c = c == ' ' ? '_' : c;
  for (std::size_t p = first_part; p < end_part; ++p) {
    auto line = impl_->lookup(p, lemma);
    if (!line) continue;
    // lemma pos synset_cnt p_cnt [ptr_symbol]... sense_cnt tagsense_cnt [synset_offset]...
    std::vector<std::string_view> f = fields(*line);
    if (f.size() < 4) continue;
    std::size_t synsets = to_number(f[2], 10);
    std::size_t at = 4 + to_number(f[3], 10) + 2;
    for (std::size_t k = 0; k < synsets && at + k < f.size(); ++k) {
      const auto rank = static_cast<int>(k);
      if (rank < senses) out.push_back(kParts[p].letter + std::string(f[at + k]));
      if (rank < hypernym_senses) {
        for (std::string& h : impl_->hypernyms(p, to_number(f[at + k], 10))) {
          out.push_back(std::move(h));
        }
      }
      if (rank >= senses && rank >= hypernym_senses) break;
    }
  }
  return out;
}

}  // namespace marvin::interpret
