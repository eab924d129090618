// The training tools' third synthesiser: every festival training voice says a word, the English
// voices follow the stretch, and a missing program or voice is an error that says what to run.
#include "kws/training/festival_voices.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <stdexcept>
#include <string>

#include "error_without_programs.h"
#include "kws/training/augment.h"
#include "kws/training/synthesiser_program.h"

namespace kws = marvin::perception::kws;

TEST_CASE("every festival training voice says a word") {
  for (const std::string& voice : kws::festival_voices()) {
    CAPTURE(voice);
    const std::vector<float> word = kws::synthesize_festival("marvin", voice, 1.0f);
    CHECK(word.size() > 16000 * 2 / 10);  // a word: more than 0.2 s
    CHECK(word.size() < 16000 * 3 / 2);
    CHECK(kws::rms(word) > 0.01f);
  }
}

TEST_CASE("an English festival voice says it slower with a larger stretch") {
  const std::vector<float> normal = kws::synthesize_festival("marvin", "kal_diphone", 1.0f);
  const std::vector<float> slow = kws::synthesize_festival("marvin", "kal_diphone", 1.5f);
  CHECK(static_cast<double>(slow.size()) > 1.3 * static_cast<double>(normal.size()));
}

TEST_CASE("the held-out festival voices speak and are not training voices") {
  const auto& voices = kws::festival_voices();
  REQUIRE(kws::festival_heldout_voices().size() == 4);
  for (const std::string& held_out : kws::festival_heldout_voices()) {
    CAPTURE(held_out);
    CHECK(std::find(voices.begin(), voices.end(), held_out) == voices.end());
    CHECK(kws::synthesize_festival("marvin", held_out, 1.0f).size() > 1600);
  }
}

TEST_CASE("without the text2wave program the error names it and scripts/setup") {
  const std::string message = kws::testing::error_without_programs(
      [] { kws::synthesize_festival("marvin", "kal_diphone", 1.0f); });
  CHECK(message.find("cannot run text2wave") != std::string::npos);
  CHECK(message.find("scripts/setup") != std::string::npos);
}

TEST_CASE("an unknown festival voice is an error naming it") {
  // text2wave itself exits 0 after the Scheme error and writes no sound.
  CHECK_THROWS_WITH_AS(kws::synthesize_festival("marvin", "nobody_diphone", 1.0f),
                       doctest::Contains("festival voice \"nobody_diphone\" said nothing"),
                       std::runtime_error);
  CHECK_THROWS_WITH_AS(kws::synthesize_festival("marvin", "kal) (quit", 1.0f),
                       doctest::Contains("festival voice \"kal) (quit\": expected a voice name"),
                       std::runtime_error);
}

TEST_CASE("a text longer than a synthesiser's input limit is refused before it runs") {
  const std::string long_text(kws::kMaxSynthesiserInput + 1, 'a');
  CHECK_THROWS_WITH_AS(kws::synthesize_festival(long_text, "kal_diphone", 1.0f),
                       doctest::Contains("text2wave: input of 4098 bytes, expected at most 4096"),
                       std::runtime_error);
}
