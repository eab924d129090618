// PersonalData kept in memory: for tests, the SDK's MockRobot and `marvin run --sim
// --in-memory`. Nothing survives the process. Thread-safe.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <mutex>
#include <string>
#include <tuple>
#include <vector>

#include "data/personal_data.h"

namespace marvin::skills {

class InMemoryPersonalData : public data::PersonalData {
 public:
  // `now_ms` stamps the event log (the host's clock, so that "since this morning" means the
  // same as with the SQLite store); without one, events are stamped 0.
  explicit InMemoryPersonalData(std::function<std::int64_t()> now_ms = {})
      : now_ms_(std::move(now_ms)) {}

  std::int64_t add_reminder(const data::Reminder& reminder) override;
  std::vector<data::Reminder> reminders_between(std::int64_t from_utc_ms,
                                                std::int64_t to_utc_ms) override;
  std::vector<data::Reminder> list_reminders() override;
  std::optional<data::Reminder> get_reminder(std::int64_t id) override;
  bool remove_reminder(std::int64_t id) override;
  bool snooze_reminder(std::int64_t id, std::int64_t until_utc_ms) override;
  bool complete_reminder(std::int64_t id) override;

  std::int64_t add_contact(const data::Contact& contact) override;
  std::vector<data::Contact> find_contacts(std::string_view name_or_alias) override;
  std::vector<data::Contact> list_contacts() override;
  bool remove_contact(std::int64_t id) override;

  std::vector<data::Person> list_people() override;
  // Test helper: people are added by the face-enrolment issue, not through PersonalData.
  std::int64_t add_person(const data::Person& person);

  std::optional<std::string> storage_get(std::string_view skill_id, std::string_view key) override;
  void storage_set(std::string_view skill_id, std::string_view key,
                   std::string_view value) override;
  bool storage_remove(std::string_view skill_id, std::string_view key) override;

  void log_event(std::string_view kind, std::string_view source, std::string_view message) override;

  struct Event {
    std::string kind, source, message;
    std::int64_t time_ms = 0;
  };
  // Oldest first.
  std::vector<Event> events();
  // Newest first, of `kind` ("" for all), at or after `since_ms`: what events_list answers.
  std::vector<Event> recent_events(std::string_view kind, std::int64_t since_ms);

 private:
  std::int64_t now() const { return now_ms_ ? now_ms_() : 0; }

  std::function<std::int64_t()> now_ms_;
  std::mutex mutex_;
  std::int64_t next_id_ = 1;
  std::map<std::int64_t, data::Reminder> reminders_;
  std::map<std::int64_t, data::Contact> contacts_;
  std::map<std::int64_t, data::Person> people_;
  std::map<std::pair<std::string, std::string>, std::string, std::less<>> storage_;
  std::vector<Event> events_;
};

}  // namespace marvin::skills
