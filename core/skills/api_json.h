// The JSON text of the Robot API's schedule, contact and people calls, and its mapping
// to PersonalData's types. The formats are documented for skill authors in
// sdk/include/marvin/README.md; this file is their one implementation.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

#include "data/personal_data.h"

namespace marvin::skills {

// {"title": "...", "at": "YYYY-MM-DDTHH:MM" (local), "time_zone"?: IANA,
//  "recurrence"?: {"kind": "once|daily|weekdays|weekly|interval", "weekdays"?: ["monday",..],
//                  "every_minutes"? | "every_seconds"?, "from"?: "HH:MM", "to"?: "HH:MM"}}
// `default_time_zone` applies when "time_zone" is absent. Throws std::runtime_error naming
// the field on bad input.
data::Reminder reminder_from_json(const nlohmann::json& json, const std::string& default_time_zone);
nlohmann::json reminder_to_json(const data::Reminder& reminder);

// {"name": "...", "aliases"?: [..], "relation"?: "...", "phone_numbers"?: [..]}
data::Contact contact_from_json(const nlohmann::json& json);
nlohmann::json contact_to_json(const data::Contact& contact);
nlohmann::json person_to_json(const data::Person& person);

// Local wall time "YYYY-MM-DDTHH:MM" in `time_zone` to UTC ms. A time in the spring gap
// maps to the end of the gap; a time in the autumn fold to its first occurrence.
std::int64_t local_to_utc_ms(std::string_view local, const std::string& time_zone);
// UTC ms to local "YYYY-MM-DDTHH:MM" in `time_zone`.
std::string utc_to_local(std::int64_t utc_ms, const std::string& time_zone);

}  // namespace marvin::skills
