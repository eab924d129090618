#include <doctest/doctest.h>

#include <optional>
#include <string>

#include "interpret/durations.h"
#include "interpret/normalizer.h"

namespace {
std::optional<std::int64_t> seconds_of(const std::string& text) {
  auto words = marvin::interpret::normalize(text);
  return marvin::interpret::parse_duration(words);
}
}  // namespace

TEST_CASE("durations: spoken forms in seconds") {
  struct Case {
    const char* text;
    std::int64_t seconds;
  };
  const Case cases[] = {
      {"20 minutes", 1200},
      {"twenty minutes", 1200},
      {"one minute", 60},
      {"a minute", 60},
      {"an hour", 3600},
      {"an hour and a half", 5400},
      {"one hour and a half", 5400},
      {"two and a half hours", 9000},
      {"half an hour", 1800},
      {"half a minute", 30},
      {"a quarter of an hour", 900},
      {"quarter of an hour", 900},
      {"three quarters of an hour", 2700},
      {"2 hours and 30 minutes", 9000},
      {"1 hour 20 minutes", 4800},
      {"90 seconds", 90},
      {"1.5 hours", 5400},
      {"twenty five secs", 25},
      {"a couple of minutes", 120},
      {"2 days", 172800},
      {"a week", 604800},
      {"1 hour, 2 minutes and 3 seconds", 3723},
  };
  for (const Case& c : cases) {
    CAPTURE(c.text);
    CHECK(seconds_of(c.text) == c.seconds);
  }
}

TEST_CASE("durations: not durations") {
  const char* cases[] = {"", "minutes", "20", "twenty", "20 apples", "an hour and", "half",
                         "half an", "0 minutes", "an hour and a half and", "hour 20",
                         "20 minutes ago", "400 days"};
  for (const char* text : cases) {
    CAPTURE(text);
    CHECK_FALSE(seconds_of(text));
  }
}
