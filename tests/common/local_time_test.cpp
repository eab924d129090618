// local_time.h: zone lookup, and the clock-change rule both the interpreter and the
// reminder store rely on (spring gap -> the transition, autumn fold -> the earlier instant).
#include "common/local_time.h"

#include <doctest/doctest.h>

#include <chrono>

namespace {

using namespace std::chrono;

marvin::LocalMs local(int y, unsigned mo, unsigned d, int h, int mi) {
  return marvin::LocalMs{date::local_days{date::year{y} / mo / d} + hours{h} + minutes{mi}};
}

marvin::UtcMs utc(int y, unsigned mo, unsigned d, int h, int mi) {
  return marvin::UtcMs{date::sys_days{date::year{y} / mo / d} + hours{h} + minutes{mi}};
}

const date::time_zone& berlin() {
  const date::time_zone* zone = marvin::find_time_zone("Europe/Berlin");
  REQUIRE(zone != nullptr);
  return *zone;
}

}  // namespace

TEST_CASE("find_time_zone: IANA names are found, anything else is nullptr") {
  const date::time_zone* zone = marvin::find_time_zone("Europe/Berlin");
  REQUIRE(zone != nullptr);
  CHECK(zone->name() == "Europe/Berlin");
  CHECK(marvin::find_time_zone("UTC") != nullptr);
  CHECK(marvin::find_time_zone("Mars/Olympus_Mons") == nullptr);
  CHECK(marvin::find_time_zone("") == nullptr);
}

TEST_CASE("ordinary times convert both ways with the zone's offset of that day") {
  // Winter: UTC+1; summer: UTC+2.
  CHECK(marvin::local_to_utc(berlin(), local(2026, 11, 21, 20, 0)) == utc(2026, 11, 21, 19, 0));
  CHECK(marvin::local_to_utc(berlin(), local(2026, 7, 1, 8, 30)) == utc(2026, 7, 1, 6, 30));
  CHECK(marvin::utc_to_local(berlin(), utc(2026, 11, 21, 19, 0)) == local(2026, 11, 21, 20, 0));
  CHECK(marvin::utc_to_local(berlin(), utc(2026, 7, 1, 6, 30)) == local(2026, 7, 1, 8, 30));
  const date::time_zone* utc_zone = marvin::find_time_zone("UTC");
  REQUIRE(utc_zone != nullptr);
  CHECK(marvin::local_to_utc(*utc_zone, local(2026, 3, 29, 2, 30)) == utc(2026, 3, 29, 2, 30));
}

TEST_CASE("spring gap: a skipped local time maps to the transition") {
  // 29 March 2026, Berlin: 02:00 local jumps to 03:00 (01:00 UTC).
  CHECK(marvin::local_to_utc(berlin(), local(2026, 3, 29, 2, 0)) == utc(2026, 3, 29, 1, 0));
  CHECK(marvin::local_to_utc(berlin(), local(2026, 3, 29, 2, 30)) == utc(2026, 3, 29, 1, 0));
  CHECK(marvin::local_to_utc(berlin(), local(2026, 3, 29, 2, 59)) == utc(2026, 3, 29, 1, 0));
  // Either side of the gap is ordinary.
  CHECK(marvin::local_to_utc(berlin(), local(2026, 3, 29, 1, 59)) == utc(2026, 3, 29, 0, 59));
  CHECK(marvin::local_to_utc(berlin(), local(2026, 3, 29, 3, 0)) == utc(2026, 3, 29, 1, 0));
}

TEST_CASE("autumn fold: a repeated local time maps to its first, earlier instant") {
  // 25 October 2026, Berlin: 03:00 local goes back to 02:00 (01:00 UTC); 02:30 happens at
  // 00:30 UTC (summer time) and again at 01:30 UTC (winter time).
  CHECK(marvin::local_to_utc(berlin(), local(2026, 10, 25, 2, 30)) == utc(2026, 10, 25, 0, 30));
  CHECK(marvin::local_to_utc(berlin(), local(2026, 10, 25, 2, 0)) == utc(2026, 10, 25, 0, 0));
  // Both instants read back as the same local time.
  CHECK(marvin::utc_to_local(berlin(), utc(2026, 10, 25, 0, 30)) == local(2026, 10, 25, 2, 30));
  CHECK(marvin::utc_to_local(berlin(), utc(2026, 10, 25, 1, 30)) == local(2026, 10, 25, 2, 30));
  CHECK(marvin::local_to_utc(berlin(), local(2026, 10, 25, 3, 0)) == utc(2026, 10, 25, 2, 0));
}
