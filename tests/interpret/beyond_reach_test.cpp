// What Marvin says when it declines a request it cannot do: the reason, by topic.
#include <doctest/doctest.h>

#include "interpret/beyond_reach.h"

using marvin::interpret::beyond_reach;

TEST_CASE("beyond reach: each topic gives its reason, whatever the phrasing") {
  const std::string weather = "Sorry, I can't tell you the weather: I work without the internet.";
  for (const char* said : {"What's the weather like?", "is it going to RAIN tomorrow",
                           "weather forecast please", "will it snow at the weekend"}) {
    CAPTURE(said);
    CHECK(beyond_reach(said) == weather);
  }
  CHECK(beyond_reach("what's in the news today") ==
        "Sorry, I can't read you the news: I work without the internet.");
  CHECK(beyond_reach("play some music") == "Sorry, I can't play music or the radio.");
  CHECK(beyond_reach("tell me a joke") == "Sorry, I don't know any jokes.");
  CHECK(beyond_reach("follow me") ==
        "Sorry, I can't follow you yet. Say \"come here\" and I'll come to you.");
  CHECK(beyond_reach("take a picture of me") ==
        "Sorry, I can't take photos for you. I can tell you what I see: ask \"what do you "
        "see\".");
  CHECK(beyond_reach("when does the next train leave") ==
        "Sorry, I can't look that up: I work without the internet.");
}

TEST_CASE("beyond reach: the first topic named wins, and phrases match whole words") {
  // A message first, though "online" names the internet too.
  CHECK(beyond_reach("send an email online to Sam")->find("messages") != std::string::npos);
  // Buying first: "online" is how, not what.
  CHECK(beyond_reach("buy more milk online") ==
        "Sorry, I can't buy or order things, and I don't keep a shopping list.");
  CHECK(beyond_reach("order me a taxi") ==
        "Sorry, I can't buy or order things, and I don't keep a shopping list.");
  // "order" alone is not buying; "rainbow" and "snowdrop" are not the weather.
  CHECK_FALSE(beyond_reach("put them in order"));
  CHECK_FALSE(beyond_reach("paint a rainbow with snowdrops"));
  CHECK_FALSE(beyond_reach("paint me a picture"));
}

TEST_CASE("beyond reach: requests with no such topic, and bad input, get nothing") {
  for (const char* said : {"what time is it", "turn on the kitchen light", "call Anna", "", "   ",
                           "\xc3\x28 \xa0\xa1"}) {
    CAPTURE(said);
    CHECK_FALSE(beyond_reach(said));
  }
}
