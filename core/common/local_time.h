// Local wall-clock time and UTC in one IANA time zone: the one rule every area uses for the
// clock changes, so that "8 pm" means the same instant to the interpreter that reads it and
// to the store that fires it.
//
// Thread-safe: the zones come from date's process-wide tz database, which is immutable
// once loaded.
#pragma once

#include <date/tz.h>

#include <chrono>
#include <string_view>

namespace marvin {

using UtcMs = date::sys_time<std::chrono::milliseconds>;
using LocalMs = date::local_time<std::chrono::milliseconds>;

// The zone called `iana_name` ("Europe/Berlin", "UTC"), or nullptr when the tz database has
// no such zone: the caller names the field it came from in its own error. The zone lives
// as long as the process (date's database owns it).
const date::time_zone* find_time_zone(std::string_view iana_name);

// The instant that a local wall-clock time stands for in `zone`. A time in the spring gap
// (a time the clocks skip) maps to the end of the gap, the transition itself; a time in the
// autumn fold (a time that happens twice) to its first, earlier instant. So a reminder set
// for a skipped time fires as soon as the clocks have jumped, and one in the repeated hour
// fires once, at its first occurrence.
UtcMs local_to_utc(const date::time_zone& zone, LocalMs local);

// The local wall-clock time of `instant` in `zone`.
LocalMs utc_to_local(const date::time_zone& zone, UtcMs instant);

}  // namespace marvin
