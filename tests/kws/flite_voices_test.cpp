// The training tools' second synthesiser: flite's voices speak, their duration follows the
// stretch, and a missing flite program is an error that says what to run.
#include "kws/training/flite_voices.h"

#include <doctest/doctest.h>

#include <stdexcept>
#include <string>

#include "error_without_programs.h"
#include "kws/training/augment.h"

namespace kws = marvin::perception::kws;

TEST_CASE("every flite voice says a word, and a larger stretch says it slower") {
  for (const std::string& voice : kws::flite_voices()) {
    CAPTURE(voice);
    const std::vector<float> normal = kws::synthesize_flite("marvin", voice, 1.0f, 120.0f);
    const std::vector<float> slow = kws::synthesize_flite("marvin", voice, 1.5f, 120.0f);
    CHECK(normal.size() > 16000 * 2 / 10);  // a word: more than 0.2 s
    CHECK(normal.size() < 16000 * 3 / 2);
    CHECK(kws::rms(normal) > 0.01f);
    CHECK(static_cast<double>(slow.size()) > 1.3 * static_cast<double>(normal.size()));
  }
}

TEST_CASE("without the flite program the error names it and scripts/setup") {
  const std::string message = kws::testing::error_without_programs(
      [] { kws::synthesize_flite("marvin", "slt", 1.0f, 150.0f); });
  CHECK(message.find("flite") != std::string::npos);
  CHECK(message.find("scripts/setup") != std::string::npos);
}

TEST_CASE("an unknown flite voice is an error naming it") {
  CHECK_THROWS_WITH_AS(kws::synthesize_flite("marvin", "nobody", 1.0f, 120.0f),
                       doctest::Contains("flite voice \"nobody\": expected one of"),
                       std::runtime_error);
}
