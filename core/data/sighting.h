// A sighting: where Marvin last saw a known person or thing (issue 22, finding). Kept in
// the store's `sightings` table (migration 6), one row per thing.
#pragma once

#include <cstdint>
#include <string>

namespace marvin::data {

struct Sighting {
  std::string what;  // a person's name ("Anna") or an object's label ("keys", "cup")
  std::string kind;  // "person" or "object"
  std::string room;  // "kitchen"; "" when the robot did not know its room
  std::string near;  // the nearest furniture or place ("kitchen table"); "" when none
  std::int64_t seen_utc_ms = 0;
};

}  // namespace marvin::data
