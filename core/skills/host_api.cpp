#include "skills/host_api.h"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cstring>
#include <exception>

#include "common/log.h"
#include "skills/api_json.h"
#include "skills/host_call.h"
#include "telephony/callee.h"

namespace marvin::skills {
namespace {

using nlohmann::json;

using host_call::fail;
using host_call::guarded;
using host_call::need;
using host_call::need_out;
using host_call::need_service;
using host_call::need_text;
using host_call::trip_status;
using host_call::trip_wait;

json parse_json_arg(SkillContext& c, const char* text, const char* what, marvin_status* status) {
  try {
    return json::parse(text);
  } catch (const json::parse_error& e) {
    c.last_error = std::string(what) + " is not valid JSON at byte " + std::to_string(e.byte);
    *status = MARVIN_ERR_INVALID;
    return json();
  }
}

const char* api_last_error(marvin_host* host) {
  if (!host) return "no skill context (host is NULL)";
  return SkillContext::from(host).last_error.c_str();
}

marvin_status api_say(marvin_host* host, const char* text) {
  return guarded(host, [&](SkillContext& c) {
    MARVIN_TRY(need_text(c, text, "text"));
    MARVIN_TRY(need_service(c, c.services().user, "speaker"));
    c.services().user->say(text);
    return MARVIN_OK;
  });
}

marvin_status api_ask(marvin_host* host, const char* question, marvin_text_out* answer) {
  return guarded(host, [&](SkillContext& c) {
    MARVIN_TRY(need_text(c, question, "question"));
    MARVIN_TRY(need_out(c, answer));
    MARVIN_TRY(need_service(c, c.services().user, "speaker"));
    if (c.cancelled()) return fail(c, MARVIN_ERR_CANCELLED, "the request was cancelled");
    std::optional<std::string> reply = c.services().user->ask(question);
    if (!reply) return fail(c, MARVIN_ERR_CANCELLED, "the user did not answer (stopped)");
    marvin_status s = write_text(answer, *reply);
    if (s != MARVIN_OK) c.last_error = "the answer did not fit the buffer";
    return s;
  });
}

marvin_status api_set_light(marvin_host* host, marvin_light light) {
  return guarded(host, [&](SkillContext& c) {
    MARVIN_TRY(need(c, "light"));
    MARVIN_TRY(need_service(c, c.services().body, "body"));
    devices::Light l;
    switch (light) {
      case MARVIN_LIGHT_OFF:
        l = devices::Light::kOff;
        break;
      case MARVIN_LIGHT_AWAITING:
        l = devices::Light::kAwaiting;
        break;
      case MARVIN_LIGHT_LISTENING:
        l = devices::Light::kListening;
        break;
      case MARVIN_LIGHT_EXECUTING:
        l = devices::Light::kExecuting;
        break;
      default:
        return fail(c, MARVIN_ERR_INVALID,
                    "unknown light " + std::to_string(static_cast<int>(light)));
    }
    c.services().body->set_light(l);
    return MARVIN_OK;
  });
}

marvin_status api_move(marvin_host* host, marvin_direction direction, uint8_t speed,
                       uint32_t duration_ms) {
  return guarded(host, [&](SkillContext& c) {
    MARVIN_TRY(need(c, "motion"));
    MARVIN_TRY(need_service(c, c.services().body, "body"));
    devices::Direction d;
    switch (direction) {
      case MARVIN_FORWARD:
        d = devices::Direction::kForward;
        break;
      case MARVIN_BACKWARD:
        d = devices::Direction::kBackward;
        break;
      case MARVIN_TURN_LEFT:
        d = devices::Direction::kLeft;
        break;
      case MARVIN_TURN_RIGHT:
        d = devices::Direction::kRight;
        break;
      default:
        return fail(c, MARVIN_ERR_INVALID,
                    "unknown direction " + std::to_string(static_cast<int>(direction)));
    }
    if (duration_ms > 10 * 60 * 1000) {
      return fail(c, MARVIN_ERR_INVALID,
                  "a move lasts at most 600000 ms, got " + std::to_string(duration_ms));
    }
    if (c.cancelled()) return fail(c, MARVIN_ERR_CANCELLED, "the request was cancelled");
    // Body::move starts the motion (the base times it and stops before obstacles); the
    // call returns when it has run its course, or at once with a stop on "stop".
    c.services().body->move(d, speed, std::chrono::milliseconds{duration_ms});
    if (c.services().wait_for_motion ? c.wait_cancelled_for(duration_ms) : c.cancelled()) {
      c.services().body->stop();
      return fail(c, MARVIN_ERR_CANCELLED, "the motion was stopped");
    }
    return MARVIN_OK;
  });
}

marvin_status api_stop(marvin_host* host) {
  return guarded(host, [&](SkillContext& c) {
    MARVIN_TRY(need(c, "motion"));
    MARVIN_TRY(need_service(c, c.services().body, "body"));
    c.services().body->stop();
    return MARVIN_OK;
  });
}

marvin_status api_tilt_head(marvin_host* host, int32_t degrees) {
  return guarded(host, [&](SkillContext& c) {
    MARVIN_TRY(need(c, "motion"));
    MARVIN_TRY(need_service(c, c.services().body, "body"));
    if (degrees < -60 || degrees > 60) {
      return fail(c, MARVIN_ERR_INVALID,
                  "the head tilts from -60 to 60 degrees, got " + std::to_string(degrees));
    }
    c.services().body->tilt_head(degrees);
    return MARVIN_OK;
  });
}

marvin_status api_go_to(marvin_host* host, const char* place) {
  return guarded(host, [&](SkillContext& c) {
    MARVIN_TRY(need(c, "motion"));
    MARVIN_TRY(need_text(c, place, "place"));
    MARVIN_TRY(need_service(c, c.services().going_places, "map to go places with"));
    if (c.cancelled()) return fail(c, MARVIN_ERR_CANCELLED, "the request was cancelled");
    navigation::GoingPlaces& going = *c.services().going_places;
    const navigation::GoResult r = going.go_to(place, trip_wait(c, going));
    return trip_status(c, going, r, "the motion was stopped");
  });
}

marvin_status api_go_stop(marvin_host* host) {
  return guarded(host, [&](SkillContext& c) {
    MARVIN_TRY(need(c, "motion"));
    if (c.services().going_places) c.services().going_places->stop();
    if (c.services().body) c.services().body->stop();
    return MARVIN_OK;
  });
}

marvin_status api_where_am_i(marvin_host* host, marvin_text_out* room) {
  return guarded(host, [&](SkillContext& c) {
    MARVIN_TRY(need(c, "sensors"));
    MARVIN_TRY(need_out(c, room));
    MARVIN_TRY(need_service(c, c.services().going_places, "map to know its room from"));
    std::optional<std::string> name = c.services().going_places->where_am_i();
    if (!name) return fail(c, MARVIN_ERR_NOT_FOUND, "the robot is between rooms");
    return write_text(room, *name);
  });
}

marvin_status api_obstacle_scan(marvin_host* host, marvin_scan_point* points, size_t capacity,
                                size_t* count) {
  return guarded(host, [&](SkillContext& c) {
    MARVIN_TRY(need(c, "sensors"));
    MARVIN_TRY(need_service(c, c.services().body, "body"));
    if (!count || (!points && capacity > 0)) {
      return fail(c, MARVIN_ERR_INVALID, "points or count is NULL");
    }
    std::vector<devices::ScanPoint> scan = c.services().body->latest_scan();
    *count = std::min(scan.size(), capacity);
    // The body stamps points with the steady clock; skills get the wall clock.
    std::int64_t steady_now =
        c.services().steady_now_ms
            ? c.services().steady_now_ms()
            : std::chrono::duration_cast<std::chrono::milliseconds>(
                  std::chrono::steady_clock::now().time_since_epoch())
                  .count();
    std::int64_t wall_now = c.services().now_ms ? c.services().now_ms() : system_now_ms();
    for (std::size_t i = 0; i < *count; ++i) {
      points[i] = marvin_scan_point{scan[i].angle_deg, scan[i].distance_m,
                                    wall_now - (steady_now - scan[i].time_ms)};
    }
    if (scan.size() > capacity) {
      return fail(c, MARVIN_ERR_TRUNCATED,
                  "the scan has " + std::to_string(scan.size()) +
                      " points, more than the capacity " + std::to_string(capacity));
    }
    return MARVIN_OK;
  });
}

marvin_status api_now(marvin_host* host, int64_t* unix_ms) {
  return guarded(host, [&](SkillContext& c) {
    if (!unix_ms) return fail(c, MARVIN_ERR_INVALID, "unix_ms is NULL");
    *unix_ms = c.services().now_ms ? c.services().now_ms() : system_now_ms();
    return MARVIN_OK;
  });
}

marvin_status api_time_zone(marvin_host* host, marvin_text_out* name) {
  return guarded(host, [&](SkillContext& c) {
    MARVIN_TRY(need_out(c, name));
    return write_text(name, c.services().time_zone);
  });
}

marvin_status write_json(SkillContext& c, marvin_text_out* out, const json& value) {
  marvin_status s = write_text(out, value.dump());
  if (s == MARVIN_ERR_TRUNCATED) c.last_error = "the result did not fit the buffer";
  return s;
}

marvin_status api_schedule_add(marvin_host* host, const char* reminder_json,
                               marvin_text_out* created_json) {
  return guarded(host, [&](SkillContext& c) {
    MARVIN_TRY(need(c, "schedule"));
    MARVIN_TRY(need_text(c, reminder_json, "reminder_json"));
    MARVIN_TRY(need_service(c, c.services().data, "personal data store"));
    marvin_status status = MARVIN_OK;
    json input = parse_json_arg(c, reminder_json, "reminder_json", &status);
    if (status != MARVIN_OK) return status;
    data::Reminder reminder;
    try {
      reminder = reminder_from_json(input, c.services().time_zone);
    } catch (const std::exception& e) {
      return fail(c, MARVIN_ERR_INVALID, std::string("reminder_json: ") + e.what());
    }
    reminder.created_by = c.skill_id();
    reminder.id = c.services().data->add_reminder(reminder);
    return created_json ? write_json(c, created_json, reminder_to_json(reminder)) : MARVIN_OK;
  });
}

marvin_status api_schedule_list(marvin_host* host, int64_t from_unix_ms, int64_t to_unix_ms,
                                marvin_text_out* reminders_json) {
  return guarded(host, [&](SkillContext& c) {
    MARVIN_TRY(need(c, "schedule"));
    MARVIN_TRY(need_out(c, reminders_json));
    MARVIN_TRY(need_service(c, c.services().data, "personal data store"));
    if (to_unix_ms < from_unix_ms) {
      return fail(c, MARVIN_ERR_INVALID, "to_unix_ms is before from_unix_ms");
    }
    json list = json::array();
    for (const data::Reminder& r : c.services().data->reminders_between(from_unix_ms, to_unix_ms)) {
      list.push_back(reminder_to_json(r));
    }
    return write_json(c, reminders_json, list);
  });
}

marvin_status api_schedule_remove(marvin_host* host, int64_t reminder_id) {
  return guarded(host, [&](SkillContext& c) {
    MARVIN_TRY(need(c, "schedule"));
    MARVIN_TRY(need_service(c, c.services().data, "personal data store"));
    if (!c.services().data->remove_reminder(reminder_id)) {
      return fail(c, MARVIN_ERR_NOT_FOUND,
                  "there is no active reminder with id " + std::to_string(reminder_id));
    }
    return MARVIN_OK;
  });
}

marvin_status api_schedule_snooze(marvin_host* host, int64_t reminder_id, int64_t until_unix_ms) {
  return guarded(host, [&](SkillContext& c) {
    MARVIN_TRY(need(c, "schedule"));
    MARVIN_TRY(need_service(c, c.services().data, "personal data store"));
    std::int64_t now = c.services().now_ms ? c.services().now_ms() : system_now_ms();
    if (until_unix_ms <= now) {
      return fail(c, MARVIN_ERR_INVALID,
                  "a reminder snoozes until a later time, got " + std::to_string(until_unix_ms) +
                      " which is not after now (" + std::to_string(now) + ")");
    }
    if (!c.services().data->snooze_reminder(reminder_id, until_unix_ms)) {
      return fail(c, MARVIN_ERR_NOT_FOUND,
                  "there is no reminder with id " + std::to_string(reminder_id) + " to snooze");
    }
    return MARVIN_OK;
  });
}

marvin_status api_schedule_done(marvin_host* host, int64_t reminder_id) {
  return guarded(host, [&](SkillContext& c) {
    MARVIN_TRY(need(c, "schedule"));
    MARVIN_TRY(need_service(c, c.services().data, "personal data store"));
    if (!c.services().data->complete_reminder(reminder_id)) {
      return fail(c, MARVIN_ERR_NOT_FOUND,
                  "there is no active or done reminder with id " + std::to_string(reminder_id));
    }
    return MARVIN_OK;
  });
}

marvin_status api_schedule_last_fired(marvin_host* host, marvin_text_out* reminder_json) {
  return guarded(host, [&](SkillContext& c) {
    MARVIN_TRY(need(c, "schedule"));
    MARVIN_TRY(need_out(c, reminder_json));
    MARVIN_TRY(need_service(c, c.services().data, "personal data store"));
    std::optional<std::int64_t> id;
    if (c.services().last_fired_reminder) id = c.services().last_fired_reminder();
    if (!id) return fail(c, MARVIN_ERR_NOT_FOUND, "no reminder has fired yet");
    std::optional<data::Reminder> reminder = c.services().data->get_reminder(*id);
    if (!reminder) {
      return fail(c, MARVIN_ERR_NOT_FOUND,
                  "the reminder that fired last (id " + std::to_string(*id) + ") no longer exists");
    }
    json j = reminder_to_json(*reminder);
    j["state"] = reminder->state == data::Reminder::State::kActive ? "active"
                 : reminder->state == data::Reminder::State::kDone ? "done"
                                                                    : "cancelled";
    return write_json(c, reminder_json, j);
  });
}

marvin_status api_contacts_find(marvin_host* host, const char* name,
                                marvin_text_out* contacts_json) {
  return guarded(host, [&](SkillContext& c) {
    MARVIN_TRY(need(c, "contacts"));
    MARVIN_TRY(need_text(c, name, "name"));
    MARVIN_TRY(need_out(c, contacts_json));
    MARVIN_TRY(need_service(c, c.services().data, "personal data store"));
    json list = json::array();
    for (const data::Contact& contact : c.services().data->find_contacts(name)) {
      list.push_back(contact_to_json(contact));
    }
    return write_json(c, contacts_json, list);
  });
}

marvin_status api_contacts_list(marvin_host* host, marvin_text_out* contacts_json) {
  return guarded(host, [&](SkillContext& c) {
    MARVIN_TRY(need(c, "contacts"));
    MARVIN_TRY(need_out(c, contacts_json));
    MARVIN_TRY(need_service(c, c.services().data, "personal data store"));
    json list = json::array();
    for (const data::Contact& contact : c.services().data->list_contacts()) {
      list.push_back(contact_to_json(contact));
    }
    return write_json(c, contacts_json, list);
  });
}

marvin_status api_contacts_add(marvin_host* host, const char* contact_json,
                               marvin_text_out* created_json) {
  return guarded(host, [&](SkillContext& c) {
    MARVIN_TRY(need(c, "contacts"));
    MARVIN_TRY(need_text(c, contact_json, "contact_json"));
    MARVIN_TRY(need_service(c, c.services().data, "personal data store"));
    marvin_status status = MARVIN_OK;
    json input = parse_json_arg(c, contact_json, "contact_json", &status);
    if (status != MARVIN_OK) return status;
    data::Contact contact;
    try {
      contact = contact_from_json(input);
    } catch (const std::exception& e) {
      return fail(c, MARVIN_ERR_INVALID, std::string("contact_json: ") + e.what());
    }
    contact.id = c.services().data->add_contact(contact);
    return created_json ? write_json(c, created_json, contact_to_json(contact)) : MARVIN_OK;
  });
}

marvin_status api_contacts_remove(marvin_host* host, int64_t contact_id) {
  return guarded(host, [&](SkillContext& c) {
    MARVIN_TRY(need(c, "contacts"));
    MARVIN_TRY(need_service(c, c.services().data, "personal data store"));
    if (!c.services().data->remove_contact(contact_id)) {
      return fail(c, MARVIN_ERR_NOT_FOUND,
                  "there is no contact with id " + std::to_string(contact_id));
    }
    return MARVIN_OK;
  });
}

marvin_status api_people_list(marvin_host* host, marvin_text_out* people_json) {
  return guarded(host, [&](SkillContext& c) {
    MARVIN_TRY(need(c, "contacts"));
    MARVIN_TRY(need_out(c, people_json));
    MARVIN_TRY(need_service(c, c.services().data, "personal data store"));
    json list = json::array();
    for (const data::Person& p : c.services().data->list_people())
      list.push_back(person_to_json(p));
    return write_json(c, people_json, list);
  });
}

marvin_status api_storage_get(marvin_host* host, const char* key, marvin_text_out* value) {
  return guarded(host, [&](SkillContext& c) {
    MARVIN_TRY(need(c, "storage"));
    MARVIN_TRY(need_text(c, key, "key"));
    MARVIN_TRY(need_out(c, value));
    MARVIN_TRY(need_service(c, c.services().data, "personal data store"));
    std::optional<std::string> stored = c.services().data->storage_get(c.skill_id(), key);
    if (!stored)
      return fail(c, MARVIN_ERR_NOT_FOUND, std::string("no value stored under \"") + key + "\"");
    marvin_status s = write_text(value, *stored);
    if (s == MARVIN_ERR_TRUNCATED) c.last_error = "the value did not fit the buffer";
    return s;
  });
}

marvin_status api_storage_set(marvin_host* host, const char* key, const char* value,
                              size_t value_length) {
  return guarded(host, [&](SkillContext& c) {
    MARVIN_TRY(need(c, "storage"));
    MARVIN_TRY(need_text(c, key, "key"));
    if (!value && value_length > 0) return fail(c, MARVIN_ERR_INVALID, "value is NULL");
    if (key[0] == '\0') return fail(c, MARVIN_ERR_INVALID, "the key is empty");
    MARVIN_TRY(need_service(c, c.services().data, "personal data store"));
    c.services().data->storage_set(c.skill_id(), key,
                                   std::string_view(value ? value : "", value_length));
    return MARVIN_OK;
  });
}

marvin_status api_storage_remove(marvin_host* host, const char* key) {
  return guarded(host, [&](SkillContext& c) {
    MARVIN_TRY(need(c, "storage"));
    MARVIN_TRY(need_text(c, key, "key"));
    MARVIN_TRY(need_service(c, c.services().data, "personal data store"));
    if (!c.services().data->storage_remove(c.skill_id(), key)) {
      return fail(c, MARVIN_ERR_NOT_FOUND, std::string("no value stored under \"") + key + "\"");
    }
    return MARVIN_OK;
  });
}

marvin_status api_log(marvin_host* host, marvin_log_level level, const char* message) {
  return guarded(host, [&](SkillContext& c) {
    MARVIN_TRY(need_text(c, message, "message"));
    LogLevel l = LogLevel::kInfo;
    switch (level) {
      case MARVIN_LOG_DEBUG:
        l = LogLevel::kDebug;
        break;
      case MARVIN_LOG_INFO:
        l = LogLevel::kInfo;
        break;
      case MARVIN_LOG_WARNING:
        l = LogLevel::kWarning;
        break;
      case MARVIN_LOG_ERROR:
        l = LogLevel::kError;
        break;
      default:
        return fail(c, MARVIN_ERR_INVALID, "unknown log level");
    }
    marvin::log(l, "skill:" + c.skill_id(), message);
    return MARVIN_OK;
  });
}

int api_is_cancelled(marvin_host* host) {
  return host && SkillContext::from(host).cancelled() ? 1 : 0;
}


marvin_status api_smarthome_set(marvin_host* host, const char* device, const char* state) {
  return guarded(host, [&](SkillContext& c) {
    MARVIN_TRY(need(c, "smarthome"));
    MARVIN_TRY(need_text(c, device, "device"));
    MARVIN_TRY(need_text(c, state, "state"));
    MARVIN_TRY(need_service(c, c.services().smarthome, "smart home connection configured"));
    // "on" and "off" are short for {"on": true} and {"on": false}.
    json wanted;
    if (std::string_view(state) == "on") {
      wanted = json{{"on", true}};
    } else if (std::string_view(state) == "off") {
      wanted = json{{"on", false}};
    } else {
      marvin_status status = MARVIN_OK;
      wanted = parse_json_arg(c, state, "state", &status);
      if (status != MARVIN_OK) return status;
    }
    if (!wanted.is_object() || wanted.empty()) {
      return fail(c, MARVIN_ERR_INVALID,
                  "state must be \"on\", \"off\" or an object with \"on\", "
                  "\"brightness\" and/or \"target_temperature\"");
    }
    for (auto it = wanted.begin(); it != wanted.end(); ++it) {
      if (it.key() == "on" && it->is_boolean()) continue;
      if (it.key() == "brightness" && it->is_number_integer() && it->get<int>() >= 0 &&
          it->get<int>() <= 100) {
        continue;
      }
      // The thermostat's own range is checked by the smart home (it knows the device).
      if (it.key() == "target_temperature" && it->is_number() && it->get<double>() > -50.0 &&
          it->get<double>() < 100.0) {
        continue;
      }
      return fail(c, MARVIN_ERR_INVALID,
                  "state." + it.key() + ": expected \"on\": true|false, \"brightness\": "
                  "0..100 or \"target_temperature\": degrees Celsius, got " + it->dump());
    }
    SmartHome::Reply reply = c.services().smarthome->set(device, wanted);
    switch (reply.result) {
      case SmartHome::Result::kDone:
        return MARVIN_OK;
      case SmartHome::Result::kNotFound:
        return fail(c, MARVIN_ERR_NOT_FOUND, reply.sentence);
      case SmartHome::Result::kInvalid:
        return fail(c, MARVIN_ERR_INVALID, reply.sentence);
      case SmartHome::Result::kUnavailable:
        return fail(c, MARVIN_ERR_UNAVAILABLE, reply.sentence);
    }
    return fail(c, MARVIN_ERR_INTERNAL, "unknown smart-home result");
  });
}

marvin_status api_smarthome_devices(marvin_host* host, marvin_text_out* devices_json) {
  return guarded(host, [&](SkillContext& c) {
    MARVIN_TRY(need(c, "smarthome"));
    MARVIN_TRY(need_out(c, devices_json));
    MARVIN_TRY(need_service(c, c.services().smarthome, "smart home connection configured"));
    return write_json(c, devices_json, c.services().smarthome->devices());
  });
}

// --- since API 1.3: phone calls --------------------------------------------------------

marvin_status need_phone(SkillContext& c) {
  MARVIN_TRY(need(c, "phone"));
  return need_service(c, c.services().telephone, "telephone");
}

marvin_status from_reply(SkillContext& c, const Telephone::Reply& reply) {
  switch (reply.result) {
    case Telephone::Result::kDone:
      return MARVIN_OK;
    case Telephone::Result::kInvalid:
      return fail(c, MARVIN_ERR_INVALID, reply.sentence);
    case Telephone::Result::kNotFound:
      return fail(c, MARVIN_ERR_NOT_FOUND, reply.sentence);
    case Telephone::Result::kUnavailable:
      break;
  }
  return fail(c, MARVIN_ERR_UNAVAILABLE, reply.sentence);
}

// The contacts as the callee resolver sees them: phone numbers first, then SIP addresses.
std::vector<telephony::CallTarget> call_targets(data::PersonalData& data) {
  std::vector<telephony::CallTarget> out;
  for (const data::Contact& contact : data.list_contacts()) {
    telephony::CallTarget t{contact.name, contact.relation, contact.aliases,
                            contact.phone_numbers};
    t.numbers.insert(t.numbers.end(), contact.sip_uris.begin(), contact.sip_uris.end());
    out.push_back(std::move(t));
  }
  return out;
}

marvin_status api_phone_resolve(marvin_host* host, const char* who, marvin_text_out* callee_json) {
  return guarded(host, [&](SkillContext& c) {
    MARVIN_TRY(need_phone(c));
    MARVIN_TRY(need_text(c, who, "who"));
    MARVIN_TRY(need_out(c, callee_json));
    MARVIN_TRY(need_service(c, c.services().data, "personal data store"));
    const std::vector<telephony::CallTarget> targets = call_targets(*c.services().data);
    telephony::Callee callee = telephony::resolve_callee(who, targets);
    // A number said aloud that belongs to a contact is that contact: "Call Doctor Brown on
    // 0123 456 789?", and announcements name them.
    if (callee.kind == telephony::Callee::Kind::kNumber) {
      auto digits = [](const std::string& text) {
        std::string d;
        for (char ch : text) {
          if (std::isdigit(static_cast<unsigned char>(ch))) d += ch;
        }
        return d;
      };
      for (const telephony::CallTarget& t : targets) {
        for (const std::string& n : t.numbers) {
          if (n.rfind("sip:", 0) != 0 && digits(n) == digits(callee.number)) {
            callee.kind = telephony::Callee::Kind::kContact;
            callee.target = t;
            callee.say = "Call " + t.name + " on " + callee.number + "?";
          }
        }
      }
    }
    static const char* kinds[] = {"contact", "number", "ambiguous", "no_number", "unknown"};
    std::string say = callee.say;
    // Nobody wants to hear a SIP address read out: "Call Anna Schmidt?".
    if (callee.kind == telephony::Callee::Kind::kContact && callee.number.rfind("sip:", 0) == 0) {
      say = "Call " + callee.target.name + "?";
    }
    return write_json(c, callee_json,
                      json{{"kind", kinds[static_cast<int>(callee.kind)]},
                           {"name", callee.target.name},
                           {"number", callee.number},
                           {"candidates", callee.candidates},
                           {"say", say}});
  });
}

marvin_status api_phone_dial(marvin_host* host, const char* number, const char* name) {
  return guarded(host, [&](SkillContext& c) {
    MARVIN_TRY(need_text(c, number, "number"));
    MARVIN_TRY(need_phone(c));
    return from_reply(c, c.services().telephone->dial(number, name ? name : ""));
  });
}

// The 1.0 call: dials and returns.
marvin_status api_phone_call(marvin_host* host, const char* number) {
  return api_phone_dial(host, number, "");
}

marvin_status api_phone_hang_up(marvin_host* host) {
  return guarded(host, [&](SkillContext& c) {
    MARVIN_TRY(need_phone(c));
    if (!c.services().telephone->hang_up()) {
      return fail(c, MARVIN_ERR_NOT_FOUND, "there is no call to hang up");
    }
    return MARVIN_OK;
  });
}

marvin_status api_phone_answer(marvin_host* host) {
  return guarded(host, [&](SkillContext& c) {
    MARVIN_TRY(need_phone(c));
    if (!c.services().telephone->answer()) {
      return fail(c, MARVIN_ERR_NOT_FOUND, "nobody is calling");
    }
    return MARVIN_OK;
  });
}

marvin_status api_phone_decline(marvin_host* host) {
  return guarded(host, [&](SkillContext& c) {
    MARVIN_TRY(need_phone(c));
    if (!c.services().telephone->decline()) {
      return fail(c, MARVIN_ERR_NOT_FOUND, "nobody is calling");
    }
    return MARVIN_OK;
  });
}

marvin_status api_phone_state(marvin_host* host, marvin_text_out* state_json) {
  return guarded(host, [&](SkillContext& c) {
    MARVIN_TRY(need_out(c, state_json));
    MARVIN_TRY(need_phone(c));
    return write_json(c, state_json, c.services().telephone->state());
  });
}

marvin_status api_phone_wait_event(marvin_host* host, uint32_t timeout_ms,
                                   marvin_text_out* event_json) {
  return guarded(host, [&](SkillContext& c) {
    MARVIN_TRY(need_out(c, event_json));
    MARVIN_TRY(need_phone(c));
    if (c.cancelled()) return fail(c, MARVIN_ERR_CANCELLED, "the request was cancelled");
    std::optional<json> event = c.services().telephone->wait_event(
        std::chrono::milliseconds{timeout_ms}, [&] { return c.cancelled(); });
    if (event) return write_json(c, event_json, *event);
    if (c.cancelled()) return fail(c, MARVIN_ERR_CANCELLED, "the request was cancelled");
    return fail(c, MARVIN_ERR_NOT_FOUND,
                "nothing happened on the phone within " + std::to_string(timeout_ms) + " ms");
  });
}

marvin_status api_phone_call_for_help(marvin_host* host) {
  return guarded(host, [&](SkillContext& c) {
    MARVIN_TRY(need_phone(c));
    MARVIN_TRY(need_service(c, c.services().data, "personal data store"));
    std::vector<data::Contact> contacts = c.services().data->list_contacts();
    std::stable_sort(contacts.begin(), contacts.end(), [](const auto& a, const auto& b) {
      return a.emergency_order < b.emergency_order;
    });
    std::vector<std::pair<std::string, std::string>> order;
    for (const data::Contact& contact : contacts) {
      if (contact.emergency_order <= 0) continue;
      const std::vector<std::string>& numbers =
          contact.phone_numbers.empty() ? contact.sip_uris : contact.phone_numbers;
      if (!numbers.empty()) order.emplace_back(contact.name, numbers.front());
    }
    if (order.empty()) {
      return fail(c, MARVIN_ERR_NOT_FOUND, "there is no emergency contact with a number");
    }
    return from_reply(c, c.services().telephone->call_for_help(std::move(order)));
  });
}

// --- since API 1.2: seeing -------------------------------------------------------------

template <class F>
marvin_status with_eyes(SkillContext& c, const char* permission, F&& body) {
  MARVIN_TRY(need(c, permission));
  MARVIN_TRY(need_service(c, c.services().eyes, "camera"));
  try {
    return body(*c.services().eyes);
  } catch (const EyesUnavailable& e) {
    return fail(c, MARVIN_ERR_UNAVAILABLE, e.what());
  } catch (const NoSingleFace& e) {
    return fail(c, e.faces() == 0 ? MARVIN_ERR_NOT_FOUND : MARVIN_ERR_INVALID, e.what());
  }
}

marvin_status api_vision_look(marvin_host* host, marvin_text_out* seen_json) {
  return guarded(host, [&](SkillContext& c) {
    MARVIN_TRY(need_out(c, seen_json));
    return with_eyes(c, "camera", [&](Eyes& eyes) {
      const std::string seen = eyes.look_json();
      record_sightings(c, seen);  // API 1.3: every look remembers who and what it saw
      marvin_status s = write_text(seen_json, seen);
      if (s == MARVIN_ERR_TRUNCATED) c.last_error = "what the camera sees did not fit the buffer";
      return s;
    });
  });
}

marvin_status api_vision_capture_photo(marvin_host* host, marvin_text_out* photo_path) {
  return guarded(host, [&](SkillContext& c) {
    MARVIN_TRY(need_out(c, photo_path));
    return with_eyes(c, "camera", [&](Eyes& eyes) {
      return write_text(photo_path, eyes.capture_photo(c.skill_id()));
    });
  });
}

marvin_status api_vision_enroll_face(marvin_host* host, const char* name, uint32_t frames,
                                     marvin_text_out* result_json) {
  return guarded(host, [&](SkillContext& c) {
    MARVIN_TRY(need_text(c, name, "name"));
    if (*name == '\0') return fail(c, MARVIN_ERR_INVALID, "name is empty");
    if (frames < 1 || frames > 20) {
      return fail(c, MARVIN_ERR_INVALID,
                  "frames is " + std::to_string(frames) + ", expected 1 to 20");
    }
    return with_eyes(c, "faces", [&](Eyes& eyes) {
      const int used = eyes.enroll_face(name, static_cast<int>(frames), "skill:" + c.skill_id());
      if (!result_json) return MARVIN_OK;
      return write_text(result_json, json{{"name", name}, {"frames_used", used}}.dump());
    });
  });
}

marvin_status api_vision_forget_face(marvin_host* host, const char* name) {
  return guarded(host, [&](SkillContext& c) {
    MARVIN_TRY(need_text(c, name, "name"));
    return with_eyes(c, "faces", [&](Eyes& eyes) {
      if (!eyes.forget_face(name, "skill:" + c.skill_id())) {
        return fail(c, MARVIN_ERR_NOT_FOUND, std::string("nobody called ") + name +
                                                 " is known by face");
      }
      return MARVIN_OK;
    });
  });
}

// The 1.0 placeholder, served since 1.2: the faces in view as [{"name", "box"}].
marvin_status api_vision_who_is_there(marvin_host* host, marvin_text_out* people_json) {
  return guarded(host, [&](SkillContext& c) {
    MARVIN_TRY(need_out(c, people_json));
    const char* permission = c.has_permission("vision") ? "vision" : "camera";
    return with_eyes(c, permission, [&](Eyes& eyes) {
      json people = json::array();
      for (const json& f : json::parse(eyes.look_json()).value("faces", json::array())) {
        people.push_back({{"name", f.value("name", "")}, {"box", f.value("box", json::array())}});
      }
      return write_text(people_json, people.dump());
    });
  });
}

marvin_status api_vision_teach_object(marvin_host* host, const char* name) {
  return guarded(host, [&](SkillContext& c) {
    MARVIN_TRY(need_text(c, name, "name"));
    if (*name == '\0') return fail(c, MARVIN_ERR_INVALID, "name is empty");
    return with_eyes(c, "camera", [&](Eyes& eyes) {
      try {
        eyes.teach_object(name);
      } catch (const std::invalid_argument& e) {
        return fail(c, MARVIN_ERR_INVALID, e.what());
      }
      return MARVIN_OK;
    });
  });
}

marvin_status api_vision_find_object(marvin_host* host, const char* name,
                                     marvin_text_out* result_json) {
  return guarded(host, [&](SkillContext& c) {
    MARVIN_TRY(need_text(c, name, "object_name"));
    MARVIN_TRY(need_out(c, result_json));
    // "vision" is the 1.0 name of this capability; "camera" the 1.2 one.
    const char* permission = c.has_permission("vision") ? "vision" : "camera";
    return with_eyes(c, permission, [&](Eyes& eyes) {
      const std::string found = eyes.find_object_json(name);
      if (found.empty()) {
        return fail(c, MARVIN_ERR_NOT_FOUND,
                    std::string("nothing called ") + name + " was shown to the robot");
      }
      return write_text(result_json, found);
    });
  });
}

}  // namespace

std::int64_t system_now_ms() {
  return std::chrono::duration_cast<std::chrono::milliseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

SkillContext::SkillContext(std::string skill_id, std::vector<std::string> permissions,
                           HostServices& services)
    : skill_id_(std::move(skill_id)), permissions_(std::move(permissions)), services_(services) {}

bool SkillContext::has_permission(const std::string& permission) const {
  return permission == "speech" ||
         std::find(permissions_.begin(), permissions_.end(), permission) != permissions_.end();
}

void SkillContext::begin_request() {
  std::lock_guard lock(mutex_);
  cancelled_.store(false);
  last_error.clear();
  kept_answer_.clear();
}

void SkillContext::cancel() {
  {
    std::lock_guard lock(mutex_);
    cancelled_.store(true);
  }
  wake_.notify_all();
}

bool SkillContext::wait_cancelled_for(std::uint32_t ms) {
  std::unique_lock lock(mutex_);
  return wake_.wait_for(lock, std::chrono::milliseconds{ms}, [&] { return cancelled_.load(); });
}

marvin_status write_text(marvin_text_out* out, std::string_view text) {
  if (!out) return MARVIN_ERR_INVALID;
  out->length = text.size();
  if (!out->data || out->capacity == 0) {
    note_truncated(out, text);  // an acting call keeps its answer for the retry
    return MARVIN_ERR_TRUNCATED;
  }
  std::size_t n = std::min(text.size(), out->capacity - 1);
  std::memcpy(out->data, text.data(), n);
  out->data[n] = '\0';
  if (n == text.size()) return MARVIN_OK;
  note_truncated(out, text);  // an acting call keeps its answer for the retry
  return MARVIN_ERR_TRUNCATED;
}

const marvin_robot_api* host_robot_api() {
  static const marvin_robot_api api = [] {
    marvin_robot_api a{};
    a.struct_size = sizeof(marvin_robot_api);
    a.major = MARVIN_ROBOT_API_MAJOR;
    a.minor = MARVIN_ROBOT_API_MINOR;
    a.last_error = api_last_error;
    a.say = api_say;
    a.ask = api_ask;
    a.set_light = api_set_light;
    a.move = api_move;
    a.stop = api_stop;
    a.tilt_head = api_tilt_head;
    a.obstacle_scan = api_obstacle_scan;
    a.now = api_now;
    a.time_zone = api_time_zone;
    a.schedule_add = api_schedule_add;
    a.schedule_list = api_schedule_list;
    a.schedule_remove = api_schedule_remove;
    a.contacts_find = api_contacts_find;
    a.contacts_add = api_contacts_add;
    a.people_list = api_people_list;
    a.storage_get = api_storage_get;
    a.storage_set = api_storage_set;
    a.storage_remove = api_storage_remove;
    a.log = api_log;
    a.is_cancelled = api_is_cancelled;
    a.vision_find_object = api_vision_find_object;
    a.vision_who_is_there = api_vision_who_is_there;
    a.phone_call = api_phone_call;
    a.smarthome_set = api_smarthome_set;
    a.schedule_snooze = api_schedule_snooze;
    a.schedule_done = api_schedule_done;
    a.schedule_last_fired = api_schedule_last_fired;
    a.vision_look = api_vision_look;
    a.vision_capture_photo = api_vision_capture_photo;
    a.vision_enroll_face = api_vision_enroll_face;
    a.vision_forget_face = api_vision_forget_face;
    a.vision_teach_object = api_vision_teach_object;
    a.go_to = api_go_to;
    a.go_stop = api_go_stop;
    a.where_am_i = api_where_am_i;
    a.smarthome_devices = api_smarthome_devices;
    add_finding_api(a);
    a.phone_resolve = api_phone_resolve;
    a.phone_dial = api_phone_dial;
    a.phone_hang_up = api_phone_hang_up;
    a.phone_answer = api_phone_answer;
    a.phone_decline = api_phone_decline;
    a.phone_state = api_phone_state;
    a.phone_wait_event = api_phone_wait_event;
    a.phone_call_for_help = api_phone_call_for_help;
    add_guiding_api(a);
    a.contacts_list = api_contacts_list;
    a.contacts_remove = api_contacts_remove;
    keep_answers_of_acting_calls(a);
    return a;
  }();
  return &api;
}

}  // namespace marvin::skills
