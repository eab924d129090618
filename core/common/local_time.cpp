#include "common/local_time.h"

#include <exception>

namespace marvin {

const date::time_zone* find_time_zone(std::string_view iana_name) {
  try {
    return date::locate_zone(iana_name);
  } catch (const std::exception&) {
    return nullptr;  // date says "not found" by throwing; callers word their own error
  }
}

UtcMs local_to_utc(const date::time_zone& zone, LocalMs local) {
  return zone.to_sys(local, date::choose::earliest);
}

LocalMs utc_to_local(const date::time_zone& zone, UtcMs instant) { return zone.to_local(instant); }

}  // namespace marvin
