#include "skills/in_memory_personal_data.h"

#include <algorithm>
#include <cctype>
#include <stdexcept>

namespace marvin::skills {
namespace {

std::string lower(std::string_view text) {
  std::string out(text);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

}  // namespace

std::int64_t InMemoryPersonalData::add_reminder(const data::Reminder& reminder) {
  if (reminder.title.empty()) throw std::runtime_error("reminder: \"title\" is empty");
  std::lock_guard lock(mutex_);
  data::Reminder stored = reminder;
  stored.id = next_id_++;
  stored.state = data::Reminder::State::kActive;
  reminders_[stored.id] = stored;
  return stored.id;
}

std::vector<data::Reminder> InMemoryPersonalData::reminders_between(std::int64_t from_utc_ms,
                                                                    std::int64_t to_utc_ms) {
  std::lock_guard lock(mutex_);
  std::vector<data::Reminder> out;
  for (const auto& [id, r] : reminders_) {
    if (r.state == data::Reminder::State::kActive && r.next_fire_utc_ms >= from_utc_ms &&
        r.next_fire_utc_ms < to_utc_ms) {
      out.push_back(r);
    }
  }
  std::stable_sort(out.begin(), out.end(), [](const auto& a, const auto& b) {
    return a.next_fire_utc_ms < b.next_fire_utc_ms;
  });
  return out;
}

std::vector<data::Reminder> InMemoryPersonalData::list_reminders() {
  std::lock_guard lock(mutex_);
  std::vector<data::Reminder> out;
  for (const auto& [id, r] : reminders_) {
    if (r.state == data::Reminder::State::kActive) out.push_back(r);
  }
  return out;
}

std::optional<data::Reminder> InMemoryPersonalData::get_reminder(std::int64_t id) {
  std::lock_guard lock(mutex_);
  auto it = reminders_.find(id);
  if (it == reminders_.end()) return std::nullopt;
  return it->second;
}

bool InMemoryPersonalData::remove_reminder(std::int64_t id) {
  std::lock_guard lock(mutex_);
  auto it = reminders_.find(id);
  if (it == reminders_.end() || it->second.state != data::Reminder::State::kActive) return false;
  it->second.state = data::Reminder::State::kCancelled;
  return true;
}

bool InMemoryPersonalData::snooze_reminder(std::int64_t id, std::int64_t until_utc_ms) {
  std::lock_guard lock(mutex_);
  auto it = reminders_.find(id);
  if (it == reminders_.end() || it->second.state == data::Reminder::State::kCancelled) return false;
  it->second.state = data::Reminder::State::kActive;
  it->second.next_fire_utc_ms = until_utc_ms;
  return true;
}

bool InMemoryPersonalData::complete_reminder(std::int64_t id) {
  std::lock_guard lock(mutex_);
  auto it = reminders_.find(id);
  if (it == reminders_.end() || it->second.state == data::Reminder::State::kCancelled) return false;
  if (it->second.recurrence.kind == data::Recurrence::Kind::kOnce) {
    it->second.state = data::Reminder::State::kDone;
  }
  events_.push_back(Event{"reminder_done", "scheduler",
                          "reminder " + std::to_string(id) + " '" + it->second.title + "' done",
                          now()});
  return true;
}

std::int64_t InMemoryPersonalData::add_contact(const data::Contact& contact) {
  if (contact.name.empty()) throw std::runtime_error("contact: \"name\" is empty");
  std::lock_guard lock(mutex_);
  data::Contact stored = contact;
  stored.id = next_id_++;
  contacts_[stored.id] = stored;
  return stored.id;
}

std::vector<data::Contact> InMemoryPersonalData::find_contacts(std::string_view name_or_alias) {
  std::string wanted = lower(name_or_alias);
  std::lock_guard lock(mutex_);
  std::vector<data::Contact> out;
  for (const auto& [id, c] : contacts_) {
    bool hit = lower(c.name) == wanted;
    for (const std::string& alias : c.aliases) hit = hit || lower(alias) == wanted;
    // The relation as people say it: "daughter", "my daughter".
    const std::string relation = lower(c.relation);
    hit = hit || (!relation.empty() && (relation == wanted || "my " + relation == wanted));
    if (hit) out.push_back(c);
  }
  return out;
}

std::vector<data::Contact> InMemoryPersonalData::list_contacts() {
  std::lock_guard lock(mutex_);
  std::vector<data::Contact> out;
  for (const auto& [id, c] : contacts_) out.push_back(c);
  // By name, as the SQLite store lists them (contacts_ is by id).
  std::stable_sort(out.begin(), out.end(),
                   [](const data::Contact& a, const data::Contact& b) { return a.name < b.name; });
  return out;
}

bool InMemoryPersonalData::remove_contact(std::int64_t id) {
  std::lock_guard lock(mutex_);
  if (contacts_.erase(id) == 0) return false;
  // As the SQLite store's ON DELETE SET NULL: the person stays, unlinked.
  for (auto& [person_id, p] : people_) {
    if (p.contact_id == id) p.contact_id.reset();
  }
  return true;
}

std::vector<data::Person> InMemoryPersonalData::list_people() {
  std::lock_guard lock(mutex_);
  std::vector<data::Person> out;
  for (const auto& [id, p] : people_) out.push_back(p);
  return out;
}

std::int64_t InMemoryPersonalData::add_person(const data::Person& person) {
  std::lock_guard lock(mutex_);
  data::Person stored = person;
  stored.id = next_id_++;
  people_[stored.id] = stored;
  return stored.id;
}

std::optional<std::string> InMemoryPersonalData::storage_get(std::string_view skill_id,
                                                             std::string_view key) {
  std::lock_guard lock(mutex_);
  auto it = storage_.find(std::make_pair(std::string(skill_id), std::string(key)));
  if (it == storage_.end()) return std::nullopt;
  return it->second;
}

void InMemoryPersonalData::storage_set(std::string_view skill_id, std::string_view key,
                                       std::string_view value) {
  std::lock_guard lock(mutex_);
  storage_[std::make_pair(std::string(skill_id), std::string(key))] = std::string(value);
}

bool InMemoryPersonalData::storage_remove(std::string_view skill_id, std::string_view key) {
  std::lock_guard lock(mutex_);
  return storage_.erase(std::make_pair(std::string(skill_id), std::string(key))) > 0;
}

void InMemoryPersonalData::log_event(std::string_view kind, std::string_view source,
                                     std::string_view message) {
  std::lock_guard lock(mutex_);
  events_.push_back(Event{std::string(kind), std::string(source), std::string(message), now()});
}

std::vector<InMemoryPersonalData::Event> InMemoryPersonalData::events() {
  std::lock_guard lock(mutex_);
  return events_;
}

std::vector<InMemoryPersonalData::Event> InMemoryPersonalData::recent_events(
    std::string_view kind, std::int64_t since_ms) {
  std::lock_guard lock(mutex_);
  std::vector<Event> out;
  for (auto it = events_.rbegin(); it != events_.rend(); ++it) {
    if (it->time_ms >= since_ms && (kind.empty() || it->kind == kind)) out.push_back(*it);
  }
  return out;
}

}  // namespace marvin::skills
