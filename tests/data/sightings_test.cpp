// The sightings table (migration 6, issue 22): one row per thing, newest first, replaced at
// every sighting; bad input is refused naming the field and nothing is stored.
#include <doctest/doctest.h>

#include <stdexcept>

#include "data/sqlite_store.h"
#include "test_support.h"

using namespace marvin::data;

TEST_CASE("sightings: one row per thing, the newest replaces the last, newest first") {
  test::TempDir dir;
  ManualClock clock(1000);
  StoreOptions o;
  o.path = dir.db();
  o.clock = &clock;
  {
    SqliteStore store(o);
    store.record_sighting({"Anna", "person", "living room", "sofa", 0});
    clock.advance(500);
    store.record_sighting({"keys", "object", "kitchen", "kitchen table", 0});
    clock.advance(500);
    store.record_sighting({"anna", "person", "kitchen", "", 0});  // names compare without case
  }
  SqliteStore again(o);  // kept across opening the file again
  const auto all = again.sightings("");
  REQUIRE(all.size() == 2);
  CHECK(all[0].what == "anna");
  CHECK(all[0].room == "kitchen");
  CHECK(all[0].seen_utc_ms == 2000);
  CHECK(all[1].what == "keys");
  CHECK(all[1].near == "kitchen table");
  CHECK(again.sightings("KEYS").size() == 1);
  CHECK(again.sightings("keys", 1501).empty());
  CHECK(again.sightings("glasses").empty());
}

TEST_CASE("sightings: bad input names the field, and nothing is stored") {
  test::TempDir dir;
  StoreOptions o;
  o.path = dir.db();
  SqliteStore store(o);
  store.record_sighting({"keys", "object", "kitchen", "", 0});
  CHECK_THROWS_WITH_AS(store.record_sighting({"", "object", "kitchen", "", 0}),
                       "sighting: 'what' is empty", std::invalid_argument);
  CHECK_THROWS_WITH_AS(store.record_sighting({"cat", "animal", "kitchen", "", 0}),
                       "sighting of cat: kind is 'animal', expected person or object",
                       std::invalid_argument);
  const auto all = store.sightings("");
  REQUIRE(all.size() == 1);
  CHECK(all[0].what == "keys");
}
