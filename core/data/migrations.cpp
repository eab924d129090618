#include "data/migrations.h"

#include <stdexcept>

#include "data/sql.h"

namespace marvin::data {
namespace {

// kMigrations[i] takes the schema from version i to i + 1. Never edit a released step:
// add a new one.
constexpr const char* kMigrations[kSchemaVersion] = {
    // 0 -> 1
    R"sql(
PRAGMA application_id = 1297241678;
CREATE TABLE reminders(
  id INTEGER PRIMARY KEY,
  title TEXT NOT NULL CHECK (title <> ''),
  first_fire_utc_ms INTEGER NOT NULL,
  time_zone TEXT NOT NULL,
  recurrence_kind INTEGER NOT NULL CHECK (recurrence_kind BETWEEN 0 AND 4),
  weekdays INTEGER NOT NULL DEFAULT 0,
  interval_minutes INTEGER NOT NULL DEFAULT 0,
  window_start_minute INTEGER NOT NULL DEFAULT 0,
  window_end_minute INTEGER NOT NULL DEFAULT 1440,
  next_fire_utc_ms INTEGER NOT NULL,
  created_by TEXT NOT NULL,
  state INTEGER NOT NULL DEFAULT 0 CHECK (state BETWEEN 0 AND 2));
CREATE TABLE contacts(
  id INTEGER PRIMARY KEY,
  name TEXT NOT NULL CHECK (name <> ''),
  relation TEXT NOT NULL DEFAULT '');
CREATE TABLE contact_aliases(
  contact_id INTEGER NOT NULL REFERENCES contacts(id) ON DELETE CASCADE,
  position INTEGER NOT NULL,
  alias TEXT NOT NULL,
  PRIMARY KEY (contact_id, position));
CREATE TABLE contact_phones(
  contact_id INTEGER NOT NULL REFERENCES contacts(id) ON DELETE CASCADE,
  position INTEGER NOT NULL,
  number TEXT NOT NULL,
  PRIMARY KEY (contact_id, position));
CREATE TABLE skill_storage(
  skill_id TEXT NOT NULL,
  key TEXT NOT NULL,
  value BLOB NOT NULL,
  PRIMARY KEY (skill_id, key)) WITHOUT ROWID;
CREATE TABLE events(
  id INTEGER PRIMARY KEY,
  time_utc_ms INTEGER NOT NULL,
  kind TEXT NOT NULL,
  source TEXT NOT NULL,
  message TEXT NOT NULL);
)sql",
    // 1 -> 2
    R"sql(
CREATE TABLE people(
  id INTEGER PRIMARY KEY,
  name TEXT NOT NULL CHECK (name <> ''),
  contact_id INTEGER REFERENCES contacts(id) ON DELETE SET NULL);
CREATE INDEX people_contact ON people(contact_id);
CREATE TABLE face_embeddings(
  id INTEGER PRIMARY KEY,
  person_id INTEGER NOT NULL REFERENCES people(id) ON DELETE CASCADE,
  model_id TEXT NOT NULL CHECK (model_id <> ''),
  dimension INTEGER NOT NULL CHECK (dimension > 0),
  data BLOB NOT NULL CHECK (length(data) = dimension * 4));
CREATE INDEX face_embeddings_person ON face_embeddings(person_id);
)sql",
    // 2 -> 3
    R"sql(
ALTER TABLE reminders ADD COLUMN created_utc_ms INTEGER NOT NULL DEFAULT 0;
ALTER TABLE reminders ADD COLUMN last_fired_utc_ms INTEGER;
CREATE INDEX reminders_due ON reminders(state, next_fire_utc_ms);
CREATE INDEX contact_aliases_alias ON contact_aliases(alias COLLATE NOCASE);
)sql",
    // 3 -> 4: the owner's names for smart-home devices ("the big lamp" -> a device name or
    // id as discovery reports it; core/home applies them).
    R"sql(
CREATE TABLE device_aliases(
  alias TEXT NOT NULL PRIMARY KEY COLLATE NOCASE CHECK (alias <> ''),
  device TEXT NOT NULL CHECK (device <> '')) WITHOUT ROWID;
)sql",
    // 4 -> 5: phone calls (issue 20): SIP addresses and the emergency order of contacts.
    R"sql(
ALTER TABLE contacts ADD COLUMN emergency_order INTEGER NOT NULL DEFAULT 0
  CHECK (emergency_order >= 0);
CREATE TABLE contact_sip_uris(
  contact_id INTEGER NOT NULL REFERENCES contacts(id) ON DELETE CASCADE,
  position INTEGER NOT NULL,
  uri TEXT NOT NULL,
  PRIMARY KEY (contact_id, position));
)sql",
    // 5 -> 6: finding (issue 22): where each known person or thing was seen last. One row
    // per thing (what + kind), replaced at every sighting, so the table stays as small as
    // the number of things Marvin knows.
    R"sql(
CREATE TABLE sightings(
  what TEXT NOT NULL COLLATE NOCASE CHECK (what <> ''),
  kind TEXT NOT NULL CHECK (kind IN ('person', 'object')),
  room TEXT NOT NULL,
  near TEXT NOT NULL,
  seen_utc_ms INTEGER NOT NULL,
  PRIMARY KEY (what, kind)) WITHOUT ROWID;
CREATE INDEX sightings_room ON sightings(room, seen_utc_ms);
)sql",
};

}  // namespace

void migrate(sqlite3* db, const std::string& path, int from, int to) {
  if (from < 0 || to > kSchemaVersion || from > to)
    throw std::runtime_error("database " + path + ": cannot migrate schema " +
                             std::to_string(from) + " to " + std::to_string(to));
  for (int v = from; v < to; ++v) {
    sql::Transaction tx(db, path);
    sql::exec(db, path, kMigrations[v]);
    sql::exec(db, path, ("PRAGMA user_version = " + std::to_string(v + 1)).c_str());
    tx.commit();
  }
}

}  // namespace marvin::data
