// The text helpers the built-in skills share (skills-builtin/common/spoken_text.h).
#include <doctest/doctest.h>

#include "common/spoken_text.h"

namespace builtin = marvin::builtin;

TEST_CASE("spoken text: names are written as names, lists are said with \"and\"") {
  CHECK(builtin::lower("Turn ON the Light") == "turn on the light");
  CHECK(builtin::capital("the door is locked") == "The door is locked");
  CHECK(builtin::capital("") == "");
  CHECK(builtin::capitalised("anna maria") == "Anna Maria");
  CHECK(builtin::capitalised("jean-luc picard") == "Jean-Luc Picard");
  CHECK(builtin::capitalised("o'brien") == "O'brien");  // only after a space or a hyphen
  CHECK(builtin::join_and({}) == "");
  CHECK(builtin::join_and({"Anna"}) == "Anna");
  CHECK(builtin::join_and({"Anna", "Ben"}) == "Anna and Ben");
  CHECK(builtin::join_and({"Anna", "Ben", "Carl"}) == "Anna, Ben and Carl");
}

TEST_CASE("spoken text: how long ago, in the unit a person would say") {
  CHECK(builtin::ago(59'999) == "just now");
  CHECK(builtin::ago(60'000) == "a minute ago");
  CHECK(builtin::ago(20 * 60'000) == "20 minutes ago");
  CHECK(builtin::ago(60 * 60'000) == "an hour ago");
  CHECK(builtin::ago(5 * 60 * 60'000 + 59 * 60'000) == "5 hours ago");
}

TEST_CASE("spoken text: a yes that lets a skill go ahead, and everything that is not one") {
  for (const char* yes : {"yes", "Yes please", "yeah", "sure", "OK", "okay, do it", "please do",
                          "go ahead", "do it", "yep"}) {
    CAPTURE(yes);
    CHECK(builtin::said_yes(yes));
  }
  for (const char* no : {"no", "", "   ", "please don't", "yes, no, wait", "not now", "maybe",
                         "I'm not sure", "nope", "yesterday", "okay no", "go", "do"}) {
    CAPTURE(no);
    CHECK_FALSE(builtin::said_yes(no));
  }
}
