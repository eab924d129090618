// The owner's personal data as the rest of the host sees it: reminders, contacts, people,
// per-skill storage and the event log.
//
// This is the seam between the skill platform (which serves the Robot API's schedule_*,
// contacts_*, people_list and storage_* calls) and the store that keeps the data. The
// real implementation is SQLite (core/data/sqlite_store.h); tests and the mock robot use
// an in-memory one. Every mutating call returns only after the change is durable, so
// whatever the robot acknowledges to the user survives a crash or a power cut.
// Implementations are safe to call from several threads.
// Errors (bad arguments, a broken database) are thrown as std::runtime_error whose message
// names the field or file that is wrong; a failed call changes nothing.
#pragma once

#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace marvin::data {

// When a reminder repeats. Times of day are local to the reminder's time zone, so "every
// day at 8" stays at 8 across daylight-saving changes.
struct Recurrence {
  enum class Kind { kOnce, kDaily, kWeekdays, kWeekly, kInterval };
  Kind kind = Kind::kOnce;
  // kWeekly: bit 0 = Monday ... bit 6 = Sunday.
  std::uint8_t weekdays = 0;
  // kInterval: every `interval_minutes` between the window's start and end (local minutes
  // of the day, end exclusive), e.g. every 4 hours from 08:00 to 20:00 for medication.
  std::int32_t interval_minutes = 0;
  std::int32_t window_start_minute = 0;
  std::int32_t window_end_minute = 24 * 60;
};

struct Reminder {
  enum class State { kActive, kDone, kCancelled };
  std::int64_t id = 0;                // assigned by the store
  std::string title;                  // "take my pills"
  std::int64_t first_fire_utc_ms = 0; // the first occurrence, UTC
  std::string time_zone;              // IANA name, e.g. "Europe/Berlin"
  Recurrence recurrence;
  std::int64_t next_fire_utc_ms = 0;  // the next occurrence still to fire, UTC
  std::string created_by;             // skill id, or "user" for the CLI
  State state = State::kActive;
};

struct Contact {
  std::int64_t id = 0;
  std::string name;                        // "Anna Schmidt"
  std::vector<std::string> aliases;        // "my daughter", "Anna"
  std::string relation;                    // "daughter"
  std::vector<std::string> phone_numbers;  // as the user gave them
  std::vector<std::string> sip_uris;       // "sip:anna@example.org" (calls over the internet)
  // 0: not an emergency contact; 1, 2, ...: the order "call for help" tries them in.
  int emergency_order = 0;
};

struct Person {
  std::int64_t id = 0;
  std::string name;
  std::optional<std::int64_t> contact_id;
};

class PersonalData {
 public:
  virtual ~PersonalData() = default;

  // Reminders. add_reminder returns the new id once committed.
  virtual std::int64_t add_reminder(const Reminder& reminder) = 0;
  // Active reminders whose next occurrence is in [from_utc_ms, to_utc_ms), soonest first.
  virtual std::vector<Reminder> reminders_between(std::int64_t from_utc_ms,
                                                  std::int64_t to_utc_ms) = 0;
  virtual std::vector<Reminder> list_reminders() = 0;  // every active reminder
  virtual std::optional<Reminder> get_reminder(std::int64_t id) = 0;
  // Marks the reminder cancelled; false if there is no active reminder with that id.
  virtual bool remove_reminder(std::int64_t id) = 0;
  // "Remind me again in ten minutes": the reminder fires next at `until_utc_ms` (a done
  // one-off reminder becomes active again), then its recurrence goes on after that instant.
  // False if there is no active or done reminder with that id. The default implementation
  // throws: stores that predate snoozing need not support it.
  virtual bool snooze_reminder(std::int64_t id, std::int64_t until_utc_ms);
  // "I took them": a one-off reminder becomes done and will not fire again; a recurring one
  // keeps its series (the occurrence that fired is acknowledged in the event log; cancel
  // the series with remove_reminder). A reminder already done (a one-off that fired) is
  // acknowledged in the log again, unchanged. False if there is no active or done reminder
  // with that id.
  // The default implementation throws.
  virtual bool complete_reminder(std::int64_t id);

  // Contacts. find_contacts matches name or alias, case-insensitively, or the relation said
  // as people say it ("daughter", "my daughter").
  virtual std::int64_t add_contact(const Contact& contact) = 0;
  virtual std::vector<Contact> find_contacts(std::string_view name_or_alias) = 0;
  virtual std::vector<Contact> list_contacts() = 0;
  virtual bool remove_contact(std::int64_t id) = 0;

  virtual std::vector<Person> list_people() = 0;

  // Per-skill key-value storage: a skill only ever reaches its own keys.
  virtual std::optional<std::string> storage_get(std::string_view skill_id,
                                                 std::string_view key) = 0;
  virtual void storage_set(std::string_view skill_id, std::string_view key,
                           std::string_view value) = 0;
  virtual bool storage_remove(std::string_view skill_id, std::string_view key) = 0;

  // The event log: intruder alerts, skill errors, missed reminders.
  virtual void log_event(std::string_view kind, std::string_view source,
                         std::string_view message) = 0;
};

inline bool PersonalData::snooze_reminder(std::int64_t, std::int64_t) {
  throw std::runtime_error("snooze_reminder: this personal data store cannot snooze reminders");
}
inline bool PersonalData::complete_reminder(std::int64_t) {
  throw std::runtime_error("complete_reminder: this personal data store cannot mark reminders done");
}

}  // namespace marvin::data
