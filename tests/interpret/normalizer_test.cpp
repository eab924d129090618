#include <doctest/doctest.h>

#include <string>
#include <vector>

#include "interpret/normalizer.h"
#include "interpret/number_words.h"

using marvin::interpret::normalize;
using Words = std::vector<std::string>;

TEST_CASE("normalize: case, punctuation, apostrophes") {
  CHECK(normalize("What's the TIME?") == Words{"what", "is", "the", "time"});
  CHECK(normalize("  Hello,   world!! ") == Words{"hello", "world"});
  CHECK(normalize("what\xE2\x80\x99s up") == Words{"what", "is", "up"});  // curly apostrophe
  CHECK(normalize("'quoted'") == Words{"quoted"});
  CHECK(normalize("at 8 o'clock") == Words{"at", "8", "o'clock"});
  CHECK(normalize("") == Words{});
  CHECK(normalize("?!.,") == Words{});
  // Contractions typed without the apostrophe, where the result is no other English word.
  CHECK(normalize("thats right") == Words{"that", "is", "right"});
  CHECK(normalize("wheres my phone") == Words{"where", "is", "my", "phone"});
  CHECK(normalize("it didnt work") == Words{"it", "did", "not", "work"});
  CHECK(normalize("i feel ill") == Words{"i", "feel", "ill"});  // "ill" is a word: kept
}

TEST_CASE("normalize: digits, clock times, am/pm") {
  CHECK(normalize("8pm") == Words{"8", "pm"});
  CHECK(normalize("8 p.m.") == Words{"8", "pm"});
  CHECK(normalize("8a.m.") == Words{"8", "am"});
  CHECK(normalize("7:30") == Words{"7:30"});
  CHECK(normalize("7:30pm.") == Words{"7:30", "pm"});
  CHECK(normalize("2.5 hours") == Words{"2.5", "hours"});
  CHECK(normalize("20min") == Words{"20", "minutes"});
  CHECK(normalize("the 21st") == Words{"the", "21st"});
  CHECK(normalize("end. Then") == Words{"end", "then"});
}

TEST_CASE("normalize: number words become digits") {
  CHECK(normalize("eight") == Words{"8"});
  CHECK(normalize("Twenty-five") == Words{"25"});
  CHECK(normalize("twenty five minutes") == Words{"25", "minutes"});
  CHECK(normalize("one hundred and five") == Words{"105"});
  CHECK(normalize("two thousand twenty four") == Words{"2024"});
  CHECK(normalize("three hundred") == Words{"300"});
  // Two units in a row stay two numbers (clock times).
  CHECK(normalize("eight thirty") == Words{"8", "30"});
  CHECK(normalize("twenty thirty") == Words{"20", "30"});
  // "and" joins only inside hundreds.
  CHECK(normalize("an hour and a half") == Words{"an", "hour", "and", "a", "half"});
  CHECK(normalize("two and a half hours") == Words{"2", "and", "a", "half", "hours"});
  CHECK(normalize("half past eight") == Words{"half", "past", "8"});
}

TEST_CASE("number word helpers") {
  using namespace marvin::interpret;
  CHECK(number_word_value("nineteen") == 19);
  CHECK(number_word_value("ninety") == 90);
  CHECK_FALSE(number_word_value("hundred"));
  CHECK_FALSE(number_word_value("eights"));
  CHECK(parse_integer("042") == 42);
  CHECK_FALSE(parse_integer("4a"));
  CHECK_FALSE(parse_integer(""));
  CHECK_FALSE(parse_integer("9999999999999999"));  // too long
  CHECK(parse_decimal("2.25") == doctest::Approx(2.25));
  CHECK_FALSE(parse_decimal("2."));
  CHECK_FALSE(parse_decimal(".5"));
}
