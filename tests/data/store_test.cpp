// SqliteStore: opening, migrations, refusals, repositories, isolation, backup.
#include <doctest/doctest.h>
#include <sqlite3.h>

#include <nlohmann/json.hpp>

#include "data/migrations.h"
#include "data/recurrence.h"
#include "data/sql.h"
#include "data/sqlite_store.h"
#include "test_support.h"

using namespace marvin::data;
using nlohmann::json;
using marvin::test_support::read_text;
using marvin::data::test::TempDir;
using marvin::test_support::write_text;

namespace {

StoreOptions at(const std::filesystem::path& path, const Clock* clock = nullptr) {
  StoreOptions o;
  o.path = path;
  o.clock = clock;
  return o;
}

Reminder pills(const char* zone = "Europe/Berlin") {
  Reminder r;
  r.title = "take my pills";
  r.time_zone = zone;
  r.first_fire_utc_ms = local_to_utc_ms("2026-12-01T20:00", zone);
  r.created_by = "schedule";
  return r;
}

Contact anna() {
  Contact c;
  c.name = "Anna Schmidt";
  c.aliases = {"my daughter"};
  c.relation = "daughter";
  c.phone_numbers = {"+49 30 1234567", "0171 555 0101"};
  return c;
}

// A raw connection for building old schemas and peeking at the file.
struct Raw {
  explicit Raw(const std::filesystem::path& p) : path(p.string()) {
    REQUIRE(sqlite3_open(path.c_str(), &db) == SQLITE_OK);
  }
  ~Raw() { sqlite3_close(db); }
  void exec(const char* sql) { sql::exec(db, path, sql); }
  std::int64_t integer(const char* query) {
    sql::Statement s(db, path, query);
    REQUIRE(s.step());
    return s.int64(0);
  }
  std::string path;
  sqlite3* db = nullptr;
};

}  // namespace

TEST_CASE("a new file is created at the newest schema, in WAL mode with durable commits") {
  TempDir dir;
  { SqliteStore store(at(dir.path() / "sub" / "marvin.db")); }
  Raw raw(dir.path() / "sub" / "marvin.db");
  CHECK(raw.integer("PRAGMA user_version") == kSchemaVersion);
  CHECK(raw.integer("PRAGMA application_id") == kApplicationId);
  sql::Statement mode(raw.db, raw.path, "PRAGMA journal_mode");
  REQUIRE(mode.step());
  CHECK(mode.text(0) == "wal");
}

TEST_CASE("the data directory follows MARVIN_DATA_DIR, then XDG_DATA_HOME, then HOME") {
  const char* keep[] = {"MARVIN_DATA_DIR", "XDG_DATA_HOME", "HOME"};
  std::string saved[3];
  bool had[3];
  for (int i = 0; i < 3; ++i) {
    const char* v = std::getenv(keep[i]);
    had[i] = v != nullptr;
    if (v) saved[i] = v;
  }
  setenv("HOME", "/home/owner", 1);
  setenv("XDG_DATA_HOME", "/xdg", 1);
  setenv("MARVIN_DATA_DIR", "/tmp/marvin-tests", 1);
  CHECK(default_data_dir() == "/tmp/marvin-tests");
  unsetenv("MARVIN_DATA_DIR");
  CHECK(default_data_dir() == "/xdg/marvin");
  unsetenv("XDG_DATA_HOME");
  CHECK(default_data_dir() == "/home/owner/.local/share/marvin");
  CHECK(database_path("/d") == "/d/marvin.db");
  for (int i = 0; i < 3; ++i) {
    if (had[i]) setenv(keep[i], saved[i].c_str(), 1);
    else unsetenv(keep[i]);
  }
}

TEST_CASE("every older schema migrates to the newest and keeps its data") {
  for (int from = 0; from < kSchemaVersion; ++from) {
    CAPTURE(from);
    TempDir dir;
    {
      Raw raw(dir.db());
      migrate(raw.db, raw.path, 0, from);
      CHECK(raw.integer("PRAGMA user_version") == from);
      if (from >= 1) {
        // Rows in the version-1 layout.
        raw.exec("INSERT INTO reminders(id, title, first_fire_utc_ms, time_zone, recurrence_kind,"
                 " next_fire_utc_ms, created_by) VALUES(7, 'water the plants', 1000, 'UTC', 1,"
                 " 86401000, 'user');"
                 "INSERT INTO contacts(id, name, relation) VALUES(3, 'Anna', 'daughter');"
                 "INSERT INTO contact_phones VALUES(3, 0, '+49 1');"
                 "INSERT INTO skill_storage VALUES('dice', 'last', x'0102');");
      }
      if (from >= 2) raw.exec("INSERT INTO people(id, name, contact_id) VALUES(5, 'Anna', 3);");
    }
    SqliteStore store(at(dir.db()));
    {
      Raw raw(dir.db());
      CHECK(raw.integer("PRAGMA user_version") == kSchemaVersion);
      // The v3 index exists whatever the starting point.
      CHECK(raw.integer("SELECT count(*) FROM sqlite_schema WHERE name = 'reminders_due'") == 1);
    }
    if (from >= 1) {
      const auto r = store.get_reminder(7);
      REQUIRE(r.has_value());
      CHECK(r->title == "water the plants");
      CHECK(r->recurrence.kind == Recurrence::Kind::kDaily);
      CHECK(r->next_fire_utc_ms == 86401000);
      CHECK(store.find_contacts("anna").at(0).phone_numbers == std::vector<std::string>{"+49 1"});
      // Schema 4 (phone calls): older contacts are no emergency contacts and have no SIP address.
      CHECK(store.find_contacts("anna").at(0).emergency_order == 0);
      CHECK(store.find_contacts("anna").at(0).sip_uris.empty());
      CHECK(store.storage_get("dice", "last") == std::string("\x01\x02"));
    }
    if (from >= 2) CHECK(store.list_people().at(0).contact_id == 3);
    // The migrated file works at the newest schema.
    const float face[3] = {0.5f, -1.0f, 2.0f};
    const auto person = store.add_person({0, "Bob", std::nullopt});
    store.add_face_embedding(person, "facenet-128", face);
    CHECK(store.face_embeddings(person).at(0).values == std::vector<float>{0.5f, -1.0f, 2.0f});
  }
}

TEST_CASE("a database from a newer Marvin is refused and left unchanged") {
  TempDir dir;
  { SqliteStore store(at(dir.db())); store.add_contact(anna()); }
  { Raw raw(dir.db()); raw.exec("PRAGMA user_version = 99"); }
  const std::string before = read_text(dir.db());
  const std::string newer = "has schema version 99, newer than this Marvin understands (" +
                            std::to_string(kSchemaVersion) + ")";
  CHECK_THROWS_WITH(SqliteStore(at(dir.db())), doctest::Contains(newer.c_str()));
  CHECK_THROWS_WITH(SqliteStore(at(dir.db())), doctest::Contains(dir.db().string().c_str()));
  CHECK(read_text(dir.db()) == before);
}

TEST_CASE("a file that is not a database is refused, named, and left byte for byte") {
  TempDir dir;
  std::string garbage;
  for (int i = 0; i < 300; ++i) garbage += "this is not an SQLite file " + std::to_string(i) + "\n";
  write_text(dir.db(), garbage);
  try {
    SqliteStore store(at(dir.db()));
    FAIL("opening a garbage file must throw");
  } catch (const sql::CorruptDatabase& e) {
    const std::string message = e.what();
    CHECK(message.find(dir.db().string()) != std::string::npos);
    CHECK(message.find("corrupted or not a Marvin database") != std::string::npos);
    CHECK(message.find("left untouched for recovery") != std::string::npos);
  }
  CHECK(read_text(dir.db()) == garbage);
  CHECK_FALSE(std::filesystem::exists(dir.path() / "marvin.db-wal"));
}

TEST_CASE("a database with a damaged page is refused and left byte for byte") {
  TempDir dir;
  {
    SqliteStore store(at(dir.db()));
    for (int i = 0; i < 200; ++i) {
      Contact c = anna();
      c.name = "Contact number " + std::to_string(i);
      store.add_contact(c);
    }
  }  // the last connection checkpoints the WAL into the file
  std::string bytes = read_text(dir.db());
  REQUIRE(bytes.size() > 4 * 4096);
  // Scribble over the middle of page 3 (a b-tree page of the contacts table or an index).
  for (std::size_t i = 2 * 4096 + 8; i < 2 * 4096 + 2000; ++i) bytes[i] = static_cast<char>(0xA5);
  write_text(dir.db(), bytes);
  CHECK_THROWS_AS(SqliteStore(at(dir.db())), sql::CorruptDatabase);
  CHECK_THROWS_WITH(SqliteStore(at(dir.db())), doctest::Contains(dir.db().string().c_str()));
  CHECK(read_text(dir.db()) == bytes);
}

TEST_CASE("a foreign SQLite file is not taken over") {
  TempDir dir;
  { Raw raw(dir.db()); raw.exec("CREATE TABLE photos(id INTEGER PRIMARY KEY)"); }
  const std::string before = read_text(dir.db());
  CHECK_THROWS_WITH(SqliteStore(at(dir.db())),
                    doctest::Contains("is an SQLite file with tables but no Marvin schema version"));
  CHECK(read_text(dir.db()) == before);
}

TEST_CASE("reminders: add, list by window, cancel, snooze, complete") {
  TempDir dir;
  ManualClock clock(1'000);
  SqliteStore store(at(dir.db(), &clock));
  const auto id = store.add_reminder(pills());
  const auto got = store.get_reminder(id);
  REQUIRE(got);
  CHECK(got->title == "take my pills");
  CHECK(got->next_fire_utc_ms == got->first_fire_utc_ms);
  CHECK(got->created_by == "schedule");
  CHECK(got->state == Reminder::State::kActive);

  Reminder daily = pills();
  daily.title = "water the plants";
  daily.recurrence.kind = Recurrence::Kind::kDaily;
  daily.first_fire_utc_ms = local_to_utc_ms("2026-12-01T09:00", "Europe/Berlin");
  const auto daily_id = store.add_reminder(daily);

  const auto day = local_to_utc_ms("2026-12-01T00:00", "Europe/Berlin");
  auto listed = store.reminders_between(day, day + 86'400'000);
  REQUIRE(listed.size() == 2);
  CHECK(listed[0].id == daily_id);  // 09:00 before 20:00
  CHECK(listed[1].id == id);
  CHECK(store.reminders_between(day + 86'400'000, day + 2 * 86'400'000).empty());
  CHECK(store.next_due_reminder()->id == daily_id);

  CHECK(store.snooze_reminder(daily_id, day + 10 * 3'600'000));
  CHECK(store.get_reminder(daily_id)->next_fire_utc_ms == day + 10 * 3'600'000);
  CHECK(store.complete_reminder(id));
  CHECK(store.get_reminder(id)->state == Reminder::State::kDone);
  CHECK(store.recent_events(1).at(0).kind == "reminder_done");
  // Done already (as a one-off is once it fired): acknowledged in the log again, unchanged.
  const std::size_t events_before = store.recent_events(100).size();
  CHECK(store.complete_reminder(id));
  CHECK(store.get_reminder(id)->state == Reminder::State::kDone);
  CHECK(store.recent_events(100).size() == events_before + 1);
  CHECK(store.recent_events(1).at(0).time_utc_ms == 1'000);
  CHECK(store.complete_reminder(daily_id));  // recurring: acknowledged, series goes on
  CHECK(store.get_reminder(daily_id)->state == Reminder::State::kActive);

  CHECK(store.remove_reminder(daily_id));
  CHECK_FALSE(store.remove_reminder(daily_id));
  CHECK(store.get_reminder(daily_id)->state == Reminder::State::kCancelled);
  CHECK(store.list_reminders().empty());
  CHECK_FALSE(store.snooze_reminder(daily_id, 5));  // cancelled stays cancelled
  const std::size_t events_now = store.recent_events(100).size();
  CHECK_FALSE(store.complete_reminder(daily_id));   // nor is it acknowledged
  CHECK_FALSE(store.complete_reminder(daily_id + 1000));
  CHECK(store.recent_events(100).size() == events_now);
}

TEST_CASE("bad reminders and contacts are refused with the field named, nothing stored") {
  TempDir dir;
  SqliteStore store(at(dir.db()));
  Reminder r = pills();
  r.time_zone = "Europe/Atlantis";
  CHECK_THROWS_WITH(store.add_reminder(r), "time_zone: unknown IANA time zone 'Europe/Atlantis'");
  r = pills();
  r.recurrence.kind = Recurrence::Kind::kInterval;
  CHECK_THROWS_WITH(store.add_reminder(r), "recurrence.interval_minutes: expected 1..1440, got 0");
  Contact c = anna();
  c.phone_numbers.push_back("call me maybe");
  CHECK_THROWS_WITH(store.add_contact(c), doctest::Contains("phone_numbers: 'call me maybe' is not a phone number"));
  c = anna();
  c.name.clear();
  CHECK_THROWS_WITH(store.add_contact(c), "name: a contact needs a name");
  c = anna();
  c.sip_uris.push_back("anna@example.org");
  CHECK_THROWS_WITH(store.add_contact(c), "sip_uris: 'anna@example.org' is not a SIP address "
                                          "(expected sip:user@host)");
  c = anna();
  c.emergency_order = -1;
  CHECK_THROWS_WITH(store.add_contact(c), doctest::Contains("emergency_order: must be 0"));
  CHECK_THROWS_WITH(store.add_person({0, "Ghost", 4242}), "contact_id: there is no contact 4242");
  const float v[2] = {1, 2};
  CHECK_THROWS_WITH(store.add_face_embedding(999, "m", v), "person_id: there is no person 999");
  CHECK(store.row_count() == 0);
  CHECK(store.face_embeddings().empty());
}

TEST_CASE("contacts: find by name, word of the name or alias, case-insensitively") {
  TempDir dir;
  SqliteStore store(at(dir.db()));
  const auto a = store.add_contact(anna());
  Contact bob;
  bob.name = "Bob Annaberg";
  bob.phone_numbers = {"555"};
  const auto b = store.add_contact(bob);
  CHECK(store.find_contacts("ANNA").size() == 1);
  CHECK(store.find_contacts("anna").at(0).id == a);
  CHECK(store.find_contacts("My Daughter").at(0).id == a);
  CHECK(store.find_contacts("annaberg").at(0).id == b);
  Contact tom;
  tom.name = "Tom";
  tom.relation = "son";
  const auto t = store.add_contact(tom);
  CHECK(store.find_contacts("my son").at(0).id == t);  // the relation, without an alias
  CHECK(store.find_contacts("Son").at(0).id == t);
  CHECK(store.find_contacts("my sons").empty());
  CHECK(store.find_contacts("ann").empty());
  CHECK(store.find_contacts("%").empty());
  CHECK(store.find_contacts("").empty());
  const Contact found = store.find_contacts("anna schmidt").at(0);
  CHECK(found.phone_numbers == anna().phone_numbers);
  CHECK(found.aliases == anna().aliases);
  CHECK(found.relation == "daughter");
  // People linked to a removed contact keep existing, unlinked.
  const auto p = store.add_person({0, "Anna", a});
  CHECK(store.remove_contact(a));
  CHECK_FALSE(store.remove_contact(a));
  CHECK(store.list_people().at(0).id == p);
  CHECK_FALSE(store.list_people().at(0).contact_id.has_value());
  CHECK(store.list_contacts().size() == 2);  // Bob and Tom
}

TEST_CASE("contacts keep SIP addresses and their emergency order, also through a backup") {
  TempDir dir;
  Contact c = anna();
  c.sip_uris = {"sip:anna@example.org", "sip:anna@127.0.0.1:5070"};
  c.emergency_order = 2;
  json backup;
  {
    SqliteStore store(at(dir.db()));
    const auto id = store.add_contact(c);
    const Contact back = store.list_contacts().at(0);
    CHECK(back.id == id);
    CHECK(back.sip_uris == c.sip_uris);
    CHECK(back.emergency_order == 2);
    backup = store.export_json();
    CHECK(backup["contacts"][0]["sip_uris"] == json(c.sip_uris));
    // A backup written before schema 4 has neither field: it still imports.
    json old = backup;
    old["contacts"][0].erase("sip_uris");
    old["contacts"][0].erase("emergency_order");
    store.import_json(old, "old.json");
    CHECK(store.list_contacts().at(0).sip_uris.empty());
    CHECK(store.list_contacts().at(0).emergency_order == 0);
    store.import_json(backup, "backup.json");
    CHECK(store.list_contacts().at(0).sip_uris == c.sip_uris);
    CHECK(store.list_contacts().at(0).emergency_order == 2);
  }
}

TEST_CASE("per-skill storage is isolated per skill id") {
  TempDir dir;
  SqliteStore store(at(dir.db()));
  store.storage_set("dice", "last", "6");
  store.storage_set("weather", "last", "rain");
  const std::string binary("\0\xff\x01", 3);
  store.storage_set("dice", "raw", binary);
  CHECK(store.storage_get("dice", "last") == "6");
  CHECK(store.storage_get("weather", "last") == "rain");
  CHECK(store.storage_get("dice", "raw") == binary);
  CHECK_FALSE(store.storage_get("weather", "raw").has_value());
  CHECK_FALSE(store.storage_remove("weather", "raw"));
  CHECK(store.storage_get("dice", "raw") == binary);
  CHECK(store.storage_remove("weather", "last"));
  CHECK(store.storage_get("dice", "last") == "6");
  store.storage_set("dice", "last", "3");
  CHECK(store.storage_get("dice", "last") == "3");
  CHECK(store.storage_get("weather", "last") == std::nullopt);
  CHECK_THROWS_WITH(store.storage_set("", "k", "v"), "skill_id: storage needs a skill id");
}

TEST_CASE("export and import round-trip everything") {
  TempDir a_dir, b_dir;
  ManualClock clock(42);
  nlohmann::json exported;
  {
    SqliteStore a(at(a_dir.db(), &clock));
    const auto id = a.add_reminder(pills());
    Reminder interval = pills("America/New_York");
    interval.recurrence.kind = Recurrence::Kind::kInterval;
    interval.recurrence.interval_minutes = 240;
    interval.recurrence.window_start_minute = 480;
    interval.recurrence.window_end_minute = 1200;
    interval.recurrence.weekdays = 0b11111;
    a.add_reminder(interval);
    a.remove_reminder(id);
    const auto c = a.add_contact(anna());
    const auto p = a.add_person({0, "Anna", c});
    const float face[4] = {0.25f, -0.5f, 1e-3f, 7.0f};
    a.add_face_embedding(p, "facenet-128", face);
    a.storage_set("dice", "raw", std::string("\0\x01\xfe", 3));
    a.log_event("intruder", "vision", "someone at the door");
    exported = a.export_json();
  }
  const std::string text = exported.dump();
  {
    SqliteStore b(at(b_dir.db(), &clock));
    b.add_contact(Contact{0, "Old", {}, "", {}, {}, 0});  // replaced by the import
    b.import_json(nlohmann::json::parse(text), "backup.json");
    CHECK(b.export_json() == exported);
    CHECK(b.find_contacts("Old").empty());
    CHECK(b.list_reminders().size() == 1);
    CHECK(b.face_embeddings().at(0).values == std::vector<float>{0.25f, -0.5f, 1e-3f, 7.0f});
    CHECK(b.storage_get("dice", "raw") == std::string("\0\x01\xfe", 3));
    // New rows continue after the imported ids.
    CHECK(b.add_contact(anna()) > b.find_contacts("Anna").front().id);
  }
}

TEST_CASE("a bad backup is refused with the field named and changes nothing") {
  TempDir dir;
  SqliteStore store(at(dir.db()));
  store.add_contact(anna());
  store.add_reminder(pills());
  store.storage_set("dice", "last", "6");
  const nlohmann::json before = store.export_json();

  auto broken = before;
  broken["reminders"][0]["time_zone"] = "Nowhere/Land";
  CHECK_THROWS_WITH(store.import_json(broken, "b.json"),
                    "b.json.reminders[0].time_zone: unknown IANA time zone 'Nowhere/Land'");
  broken = before;
  broken["contacts"][0]["phone_numbers"] = {"12", 3};
  CHECK_THROWS_WITH(store.import_json(broken, "b.json"),
                    "b.json.contacts[0].phone_numbers: expected an array of strings");
  broken = before;
  broken["storage"][0]["value"] = "not*base64";
  CHECK_THROWS_WITH(store.import_json(broken, "b.json"),
                    doctest::Contains("b.json.storage[0].value: not base64"));
  broken = before;
  broken["people"] = {{{"id", 1}, {"name", "Anna"}, {"contact_id", 77}, {"faces", nlohmann::json::array()}}};
  CHECK_THROWS_WITH(store.import_json(broken, "b.json"),
                    "b.json.people[0].contact_id: there is no contact 77 in the backup");
  broken = before;
  broken["reminders"][0]["state"] = "sleeping";
  CHECK_THROWS_WITH(store.import_json(broken, "b.json"),
                    doctest::Contains("b.json.reminders[0].state: unknown value 'sleeping'"));
  broken = before;
  broken.erase("events");
  CHECK_THROWS_WITH(store.import_json(broken, "b.json"), "b.json.events: expected an array");
  CHECK_THROWS_WITH(store.import_json(nlohmann::json::array(), "b.json"),
                    doctest::Contains("b.json: format"));
  CHECK(store.export_json() == before);
}

TEST_CASE("device aliases: kept across opening, replaced, case-blind; bad input changes nothing") {
  TempDir dir;
  {
    SqliteStore store(at(dir.db()));
    store.set_device_alias("the big lamp", "living room lamp");
    store.set_device_alias("telly", "tv");
    store.set_device_alias("Telly", "z2m:living room/tv");  // same alias, new device
  }
  SqliteStore store(at(dir.db()));
  using Pairs = std::vector<std::pair<std::string, std::string>>;
  CHECK(store.device_aliases() ==
        Pairs{{"telly", "z2m:living room/tv"}, {"the big lamp", "living room lamp"}});
  CHECK_THROWS_WITH_AS(store.set_device_alias("", "tv"), "alias: a device alias must not be empty",
                       std::invalid_argument);
  CHECK_THROWS_WITH_AS(store.set_device_alias("box", ""),
                       "device: name the device the alias means", std::invalid_argument);
  CHECK(store.device_aliases().size() == 2);
  CHECK(store.remove_device_alias("THE BIG LAMP"));
  CHECK_FALSE(store.remove_device_alias("the big lamp"));
  CHECK(store.device_aliases() == Pairs{{"telly", "z2m:living room/tv"}});
}

TEST_CASE("writing events tells the watchers after the commit; other writes and unwatched ones do not") {
  TempDir dir;
  SqliteStore store(at(dir.db()));
  std::vector<std::int64_t> seen;  // the newest event id each watcher call could read
  const auto token = store.events_written().watch([&] {
    const auto latest = store.recent_events(1);  // the lock is free and the row committed
    seen.push_back(latest.empty() ? 0 : latest.front().id);
  });
  store.add_contact(anna());
  store.add_reminder(pills());
  CHECK(seen.empty());
  store.log_event("intruder", "guard", "someone in the hall");
  REQUIRE(seen.size() == 1);
  CHECK(seen[0] == store.recent_events(1).front().id);

  // A reminder the scheduler retires with an event (a missed one) tells too; without: not.
  const Reminder r = *store.get_reminder(store.list_reminders().front().id);
  CHECK(store.advance_reminder(r.id, r.next_fire_utc_ms, r.next_fire_utc_ms,
                               r.next_fire_utc_ms + 60000));
  CHECK(seen.size() == 1);
  CHECK(store.advance_reminder(r.id, r.next_fire_utc_ms + 60000, r.next_fire_utc_ms + 60000,
                               std::nullopt, "reminder_missed", "take my pills"));
  REQUIRE(seen.size() == 2);
  CHECK(store.recent_events(1).front().kind == "reminder_missed");

  // A refused event (no kind) changes nothing and tells nobody.
  CHECK_THROWS_WITH(store.log_event("", "x", "y"), "kind: an event needs a kind");
  CHECK(seen.size() == 2);

  store.events_written().unwatch(token);
  store.log_event("note", "test", "after unwatch");
  CHECK(seen.size() == 2);
}
