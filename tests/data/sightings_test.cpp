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

TEST_CASE("sightings travel in a backup: export, import elsewhere, the same rows and times") {
  test::TempDir a_dir, b_dir;
  ManualClock clock(1000);
  StoreOptions a_options;
  a_options.path = a_dir.db();
  a_options.clock = &clock;
  nlohmann::json backup;
  {
    SqliteStore a(a_options);
    a.record_sighting({"Anna", "person", "living room", "sofa", 0});
    clock.set(2000);
    a.record_sighting({"keys", "object", "kitchen", "kitchen table", 0});
    backup = a.export_json();
  }
  REQUIRE(backup["sightings"].size() == 2);
  StoreOptions b_options;
  b_options.path = b_dir.db();
  SqliteStore b(b_options);
  b.record_sighting({"cup", "object", "bedroom", "", 0});  // replaced by the import
  b.import_json(nlohmann::json::parse(backup.dump()), "backup.json");
  const auto all = b.sightings("");
  REQUIRE(all.size() == 2);
  CHECK(all[0].what == "keys");
  CHECK(all[0].near == "kitchen table");
  CHECK(all[0].seen_utc_ms == 2000);
  CHECK(all[1].what == "Anna");
  CHECK(all[1].kind == "person");
  CHECK(all[1].room == "living room");
  CHECK(all[1].seen_utc_ms == 1000);
  CHECK(b.export_json() == backup);
  CHECK(b.row_count() == 2);  // an import over sightings alone needs --replace

  // A backup from before sightings existed restores the rest and clears them.
  nlohmann::json old = backup;
  old.erase("sightings");
  b.import_json(old, "old.json");
  CHECK(b.sightings("").empty());
}

TEST_CASE("sightings in a bad backup: the field is named and nothing changes") {
  test::TempDir dir;
  StoreOptions o;
  o.path = dir.db();
  SqliteStore store(o);
  store.record_sighting({"keys", "object", "kitchen", "", 0});
  const nlohmann::json before = store.export_json();

  auto broken = before;
  broken["sightings"][0]["kind"] = "animal";
  CHECK_THROWS_WITH(store.import_json(broken, "b.json"),
                    "b.json.sightings[0].kind: unknown value 'animal' (expected person, object)");
  broken = before;
  broken["sightings"][0]["what"] = "";
  CHECK_THROWS_WITH(store.import_json(broken, "b.json"),
                    "b.json.sightings[0].what: empty (expected a name or a thing)");
  broken = before;
  broken["sightings"][0].erase("seen_utc_ms");
  CHECK_THROWS_WITH(store.import_json(broken, "b.json"), "b.json.sightings[0].seen_utc_ms: missing");
  broken = before;
  broken["sightings"].push_back(before["sightings"][0]);
  broken["sightings"][1]["what"] = "KEYS";
  CHECK_THROWS_WITH(store.import_json(broken, "b.json"),
                    "b.json.sightings[1]: duplicate sighting of object 'KEYS'");
  broken = before;
  broken["sightings"] = "keys";
  CHECK_THROWS_WITH(store.import_json(broken, "b.json"), "b.json.sightings: expected an array");
  CHECK(store.export_json() == before);
}
