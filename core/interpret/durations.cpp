#include "interpret/durations.h"

#include <cmath>
#include <string_view>

#include "interpret/number_words.h"

namespace marvin::interpret {
namespace {

bool is_article(const std::string& w) { return w == "a" || w == "an" || w == "1"; }

// Parser over the token span; each read_* consumes on success and restores on failure.
class DurationReader {
 public:
  explicit DurationReader(std::span<const std::string> words) : words_(words) {}

  bool done() const { return at_ == words_.size(); }

  // One term: "<amount> <unit> [and a half]" | "half a/an <unit>" |
  // "[a] quarter of a/an <unit>" | "3 quarters of an <unit>" | "<n> and a half <unit>s".
  std::optional<double> read_term() {
    std::size_t start = at_;
    if (auto v = read_fraction_of_unit()) return v;
    at_ = start;
    auto amount = read_amount();
    if (!amount) return reset(start);
    // "2 and a half hours"
    if (accept_seq({"and", "a", "half"})) *amount += 0.5;
    auto unit = read_unit();
    if (!unit) return reset(start);
    double seconds = *amount * static_cast<double>(*unit);
    // "an hour and a half", "2 hours and a half"
    std::size_t before_half = at_;
    if (accept_seq({"and", "a", "half"})) {
      seconds += 0.5 * static_cast<double>(*unit);
    } else {
      at_ = before_half;
    }
    return seconds;
  }

  // "and" between terms is optional: "1 hour 20 minutes", "2 hours and 30 minutes".
  bool accept_joiner() {
    if (at_ < words_.size() && words_[at_] == "and") {
      ++at_;
      return true;
    }
    return false;
  }
  std::size_t position() const { return at_; }
  void seek(std::size_t at) { at_ = at; }

 private:
  std::optional<double> reset(std::size_t start) {
    at_ = start;
    return std::nullopt;
  }

  bool accept(std::string_view word) {
    if (at_ < words_.size() && words_[at_] == word) {
      ++at_;
      return true;
    }
    return false;
  }

  bool accept_seq(std::initializer_list<std::string_view> seq) {
    std::size_t start = at_;
    for (auto w : seq) {
      if (!accept(w)) {
        at_ = start;
        return false;
      }
    }
    return true;
  }

  std::optional<double> read_amount() {
    if (at_ >= words_.size()) return std::nullopt;
    const std::string& w = words_[at_];
    if (w == "a" || w == "an") {
      ++at_;
      if (accept("couple")) {
        accept("of");
        return 2.0;
      }
      return 1.0;
    }
    if (auto v = parse_decimal(w)) {
      ++at_;
      return v;
    }
    return std::nullopt;
  }

  std::optional<std::int64_t> read_unit() {
    if (at_ >= words_.size()) return std::nullopt;
    auto unit = duration_unit_seconds(words_[at_]);
    if (unit) ++at_;
    return unit;
  }

  std::optional<double> read_fraction_of_unit() {
    double fraction = 0;
    if (accept("half")) {
      fraction = 0.5;
    } else if (accept_seq({"a", "quarter"}) || accept("quarter")) {
      fraction = 0.25;
      if (!accept("of")) return std::nullopt;
    } else if (accept_seq({"3", "quarters", "of"})) {
      fraction = 0.75;
    } else {
      return std::nullopt;
    }
    if (at_ >= words_.size() || !is_article(words_[at_])) return std::nullopt;
    ++at_;
    auto unit = read_unit();
    if (!unit) return std::nullopt;
    return fraction * static_cast<double>(*unit);
  }

  std::span<const std::string> words_;
  std::size_t at_ = 0;
};

}  // namespace

std::optional<std::int64_t> duration_unit_seconds(const std::string& word) {
  if (word == "second" || word == "seconds" || word == "sec" || word == "secs" || word == "s")
    return 1;
  if (word == "minute" || word == "minutes" || word == "min" || word == "mins") return 60;
  if (word == "hour" || word == "hours" || word == "hr" || word == "hrs" || word == "h")
    return 3600;
  if (word == "day" || word == "days") return 86400;
  if (word == "week" || word == "weeks") return 7 * 86400;
  return std::nullopt;
}

std::optional<std::int64_t> parse_duration(std::span<const std::string> words) {
  if (words.empty() || words.size() > 12) return std::nullopt;
  DurationReader reader(words);
  double total = 0;
  auto first = reader.read_term();
  if (!first) return std::nullopt;
  total += *first;
  while (!reader.done()) {
    std::size_t before = reader.position();
    reader.accept_joiner();
    auto next = reader.read_term();
    if (!next) {
      reader.seek(before);
      return std::nullopt;
    }
    total += *next;
  }
  if (total <= 0 || total > 366.0 * 86400.0) return std::nullopt;
  return static_cast<std::int64_t>(std::llround(total));
}

}  // namespace marvin::interpret
