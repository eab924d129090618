// The schema of the personal data file and how it evolves.
//
// PRAGMA user_version is the schema version: 0 is an empty file, kSchemaVersion the
// newest this build knows. Each migration N-1 -> N runs in one transaction that also sets
// user_version = N, so a crash leaves the file at N-1 or N, never in between.
// application_id marks the file as Marvin's so a foreign SQLite file is not migrated.
//
// History:
//   1  reminders, contacts (aliases, phone numbers), per-skill storage, event log
//   2  people and their face embeddings
//   3  reminders: created/last-fired times and the (state, next fire) index the scheduler
//      uses; alias lookup index
//   4  smart-home device aliases
//   5  SIP addresses and the emergency order of contacts
//   6  sightings: where each known person or thing was seen last (issue 22)
#pragma once

#include <sqlite3.h>

#include <cstdint>
#include <string>

namespace marvin::data {

inline constexpr int kSchemaVersion = 6;
inline constexpr std::int32_t kApplicationId = 0x4d52564e;  // "MRVN"

// Migrates `db` (already open, at version `from`) to `to` <= kSchemaVersion, one
// transaction per step. Tests use it to build the older schemas. Throws naming `path`.
void migrate(sqlite3* db, const std::string& path, int from, int to);

}  // namespace marvin::data
