#include "skills/api_json.h"

#include <date/tz.h>

#include <array>
#include <chrono>
#include <regex>
#include <stdexcept>

namespace marvin::skills {
namespace {

using nlohmann::json;

const std::array<const char*, 7> kWeekdays = {"monday", "tuesday",  "wednesday", "thursday",
                                              "friday", "saturday", "sunday"};

[[noreturn]] void bad(const std::string& field, const std::string& problem) {
  throw std::runtime_error("\"" + field + "\": " + problem);
}

std::string string_field(const json& j, const char* key, bool required) {
  auto it = j.find(key);
  if (it == j.end()) {
    if (required) bad(key, "missing");
    return {};
  }
  if (!it->is_string()) bad(key, "expected a string");
  return it->get<std::string>();
}

std::vector<std::string> string_list(const json& j, const char* key) {
  std::vector<std::string> out;
  auto it = j.find(key);
  if (it == j.end()) return out;
  if (!it->is_array()) bad(key, "expected an array of strings");
  for (const json& item : *it) {
    if (!item.is_string()) bad(key, "expected an array of strings");
    out.push_back(item.get<std::string>());
  }
  return out;
}

std::int32_t minute_of_day(const std::string& field, const std::string& text) {
  static const std::regex pattern(R"(^([01][0-9]|2[0-4]):([0-5][0-9])$)");
  std::smatch m;
  if (!std::regex_match(text, m, pattern)) bad(field, "expected \"HH:MM\", got \"" + text + "\"");
  int minutes = std::stoi(m[1]) * 60 + std::stoi(m[2]);
  if (minutes > 24 * 60) bad(field, "after 24:00");
  return minutes;
}

const date::time_zone* zone(const std::string& name) {
  try {
    return date::locate_zone(name);
  } catch (const std::exception&) {
    throw std::runtime_error("unknown time zone \"" + name + "\"");
  }
}

}  // namespace

std::int64_t local_to_utc_ms(std::string_view local, const std::string& time_zone) {
  static const std::regex pattern(R"(^(\d{4})-(\d{2})-(\d{2})T(\d{2}):(\d{2})$)");
  std::string text(local);
  std::smatch m;
  if (!std::regex_match(text, m, pattern)) {
    bad("at", "expected local time \"YYYY-MM-DDTHH:MM\", got \"" + text + "\"");
  }
  date::year_month_day day{date::year{std::stoi(m[1])},
                           date::month{static_cast<unsigned>(std::stoi(m[2]))},
                           date::day{static_cast<unsigned>(std::stoi(m[3]))}};
  int hour = std::stoi(m[4]);
  int minute = std::stoi(m[5]);
  if (!day.ok() || hour > 23 || minute > 59) bad("at", "no such date or time: \"" + text + "\"");
  auto local_time = date::local_days{day} + std::chrono::hours{hour} + std::chrono::minutes{minute};
  const date::time_zone* tz = zone(time_zone);
  date::local_info info = tz->get_info(local_time);
  date::sys_seconds utc;
  switch (info.result) {
    case date::local_info::unique:
    case date::local_info::ambiguous:  // the fold: the first occurrence
      utc = date::sys_seconds{local_time.time_since_epoch()} - info.first.offset;
      break;
    case date::local_info::nonexistent:  // the gap: its end
      utc = info.second.begin;
      break;
  }
  return std::chrono::duration_cast<std::chrono::milliseconds>(utc.time_since_epoch()).count();
}

std::string utc_to_local(std::int64_t utc_ms, const std::string& time_zone) {
  auto sys = date::sys_time<std::chrono::milliseconds>{std::chrono::milliseconds{utc_ms}};
  auto local =
      date::make_zoned(zone(time_zone), date::floor<std::chrono::minutes>(sys)).get_local_time();
  return date::format("%Y-%m-%dT%H:%M", local);
}

data::Reminder reminder_from_json(const json& j, const std::string& default_time_zone) {
  if (!j.is_object()) throw std::runtime_error("a reminder must be a JSON object");
  data::Reminder r;
  r.title = string_field(j, "title", true);
  if (r.title.empty()) bad("title", "must not be empty");
  r.time_zone = string_field(j, "time_zone", false);
  if (r.time_zone.empty()) r.time_zone = default_time_zone;
  r.first_fire_utc_ms = local_to_utc_ms(string_field(j, "at", true), r.time_zone);
  // Optional "utc_ms": the exact instant within that minute (a 90-second timer), which
  // must lie in the minute "at" names.
  if (auto exact = j.find("utc_ms"); exact != j.end()) {
    if (!exact->is_number_integer()) bad("utc_ms", "expected an integer (ms since the epoch)");
    const auto ms = exact->get<std::int64_t>();
    if (ms < r.first_fire_utc_ms || ms >= r.first_fire_utc_ms + 60'000) {
      bad("utc_ms", "must lie in the minute \"at\" names");
    }
    r.first_fire_utc_ms = ms;
  }
  r.next_fire_utc_ms = r.first_fire_utc_ms;
  auto rec = j.find("recurrence");
  if (rec != j.end() && !rec->is_null()) {
    if (!rec->is_object()) bad("recurrence", "expected an object");
    std::string kind = string_field(*rec, "kind", true);
    using Kind = data::Recurrence::Kind;
    if (kind == "once") {
      r.recurrence.kind = Kind::kOnce;
    } else if (kind == "daily") {
      r.recurrence.kind = Kind::kDaily;
    } else if (kind == "weekdays") {
      r.recurrence.kind = Kind::kWeekdays;
    } else if (kind == "weekly") {
      r.recurrence.kind = Kind::kWeekly;
    } else if (kind == "interval") {
      r.recurrence.kind = Kind::kInterval;
    } else {
      bad("recurrence.kind",
          "expected once, daily, weekdays, weekly or interval, got \"" + kind + "\"");
    }
    for (const std::string& day : string_list(*rec, "weekdays")) {
      std::size_t i = 0;
      while (i < kWeekdays.size() && day != kWeekdays[i]) ++i;
      if (i == kWeekdays.size()) bad("recurrence.weekdays", "unknown day \"" + day + "\"");
      r.recurrence.weekdays = static_cast<std::uint8_t>(r.recurrence.weekdays | (1u << i));
    }
    if (r.recurrence.kind == Kind::kWeekly && r.recurrence.weekdays == 0) {
      bad("recurrence.weekdays", "a weekly reminder needs at least one day");
    }
    if (r.recurrence.kind == Kind::kInterval) {
      std::int64_t minutes = 0;
      if (auto it = rec->find("every_minutes"); it != rec->end() && it->is_number_integer()) {
        minutes = it->get<std::int64_t>();
      } else if (auto s = rec->find("every_seconds"); s != rec->end() && s->is_number_integer()) {
        minutes = s->get<std::int64_t>() / 60;
      }
      if (minutes < 1 || minutes > 24 * 60) {
        bad("recurrence.every_minutes", "expected 1 to 1440 minutes");
      }
      r.recurrence.interval_minutes = static_cast<std::int32_t>(minutes);
      std::string from = string_field(*rec, "from", false);
      std::string to = string_field(*rec, "to", false);
      if (!from.empty()) r.recurrence.window_start_minute = minute_of_day("recurrence.from", from);
      if (!to.empty()) r.recurrence.window_end_minute = minute_of_day("recurrence.to", to);
      if (r.recurrence.window_end_minute <= r.recurrence.window_start_minute) {
        bad("recurrence.to", "must be after \"from\"");
      }
    }
  }
  return r;
}

json reminder_to_json(const data::Reminder& r) {
  using Kind = data::Recurrence::Kind;
  json rec = json::object();
  switch (r.recurrence.kind) {
    case Kind::kOnce:
      rec["kind"] = "once";
      break;
    case Kind::kDaily:
      rec["kind"] = "daily";
      break;
    case Kind::kWeekdays:
      rec["kind"] = "weekdays";
      break;
    case Kind::kWeekly:
      rec["kind"] = "weekly";
      break;
    case Kind::kInterval:
      rec["kind"] = "interval";
      rec["every_minutes"] = r.recurrence.interval_minutes;
      rec["from"] = date::format("%H:%M", std::chrono::minutes{r.recurrence.window_start_minute});
      rec["to"] = date::format("%H:%M", std::chrono::minutes{r.recurrence.window_end_minute});
      break;
  }
  if (r.recurrence.weekdays != 0) {
    json days = json::array();
    for (std::size_t i = 0; i < kWeekdays.size(); ++i) {
      if (r.recurrence.weekdays & (1u << i)) days.push_back(kWeekdays[i]);
    }
    rec["weekdays"] = days;
  }
  return json{{"id", r.id},
              {"title", r.title},
              {"at", utc_to_local(r.next_fire_utc_ms, r.time_zone)},
              {"time_zone", r.time_zone},
              {"recurrence", rec},
              {"next_fire_utc_ms", r.next_fire_utc_ms},
              {"created_by", r.created_by}};
}

data::Contact contact_from_json(const json& j) {
  if (!j.is_object()) throw std::runtime_error("a contact must be a JSON object");
  data::Contact c;
  c.name = string_field(j, "name", true);
  if (c.name.empty()) bad("name", "must not be empty");
  c.aliases = string_list(j, "aliases");
  c.relation = string_field(j, "relation", false);
  c.phone_numbers = string_list(j, "phone_numbers");
  c.sip_uris = string_list(j, "sip_uris");
  if (auto it = j.find("emergency_order"); it != j.end()) {
    if (!it->is_number_integer() || it->get<int>() < 0)
      bad("emergency_order", "must be 0 (none) or 1, 2, ... (the order calls for help try)");
    c.emergency_order = it->get<int>();
  }
  return c;
}

json contact_to_json(const data::Contact& c) {
  return json{{"id", c.id},
              {"name", c.name},
              {"aliases", c.aliases},
              {"relation", c.relation},
              {"phone_numbers", c.phone_numbers},
              {"sip_uris", c.sip_uris},
              {"emergency_order", c.emergency_order}};
}

json person_to_json(const data::Person& p) {
  json j{{"id", p.id}, {"name", p.name}};
  j["contact_id"] = p.contact_id ? json(*p.contact_id) : json(nullptr);
  return j;
}

}  // namespace marvin::skills
