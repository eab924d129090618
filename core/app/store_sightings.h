// The sightings log (core/skills/sightings.h) in the owner's SQLite store.
#pragma once

#include "data/sqlite_store.h"
#include "skills/sightings.h"

namespace marvin::app {

class StoreSightingLog final : public skills::SightingLog {
 public:
  explicit StoreSightingLog(data::SqliteStore& store) : store_(store) {}
  void record(const data::Sighting& s) override { store_.record_sighting(s); }
  std::vector<data::Sighting> find(std::string_view what, std::int64_t since_utc_ms) override {
    return store_.sightings(what, since_utc_ms);
  }

 private:
  data::SqliteStore& store_;
};

}  // namespace marvin::app
