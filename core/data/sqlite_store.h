// SqliteStore: the owner's personal data in one SQLite file.
//
// The file lives at <data dir>/marvin.db, where the data directory is, in order:
// $MARVIN_DATA_DIR, $XDG_DATA_HOME/marvin, ~/.local/share/marvin (default_data_dir()).
//
// Durability: the file is in WAL mode with synchronous=FULL, so every mutating call
// returns only after its transaction's WAL frames were fsync()ed: a commit that returned
// survives a crash of the process and a power cut (given a disk that honours fsync).
// synchronous=NORMAL would be faster but in WAL mode can lose the last commits on power
// loss, which would break "acknowledged means stored". Foreign keys are on; a busy
// timeout (default 5 s) lets the CLI and the host share the file.
//
// Opening never destroys data: a file that is not a database or fails PRAGMA quick_check
// is refused with sql::CorruptDatabase naming the file, and left byte-for-byte as it was;
// a file written by a newer Marvin (user_version above kSchemaVersion) or another
// application is refused before anything is written. Older schemas are migrated, one
// transaction per step (migrations.h).
//
// Thread-safe: one connection guarded by a mutex. Every call is one transaction; a call
// that throws changed nothing.
#pragma once

#include <filesystem>
#include <memory>
#include <mutex>
#include <nlohmann/json_fwd.hpp>
#include <span>
#include <optional>
#include <string>

#include "data/change_signal.h"
#include "data/clock.h"
#include "data/personal_data.h"
#include "data/sighting.h"

struct sqlite3;

namespace marvin::data {

struct StoreOptions {
  // The database file. Its directory is created if missing.
  std::filesystem::path path;
  // FULL (default): durable commits. OFF: no fsync at all, for benchmark baselines only.
  enum class Sync { kFull, kOff };
  Sync synchronous = Sync::kFull;
  int busy_timeout_ms = 5000;
  // PRAGMA quick_check at open (O(file size); ~ms for 10,000 reminders).
  bool verify_on_open = true;
  // Stamps events and creation times; not owned, must outlive the store. Null: system clock.
  const Clock* clock = nullptr;
};

// One face embedding of a person: `values.size()` floats produced by model `model_id`.
struct FaceEmbedding {
  std::int64_t id = 0;
  std::int64_t person_id = 0;
  std::string model_id;
  std::vector<float> values;
};

struct Event {
  std::int64_t id = 0;
  std::int64_t time_utc_ms = 0;
  std::string kind;
  std::string source;
  std::string message;
};

// $MARVIN_DATA_DIR, else $XDG_DATA_HOME/marvin, else $HOME/.local/share/marvin.
// Throws if none of these variables is set.
std::filesystem::path default_data_dir();
// <data_dir>/marvin.db
std::filesystem::path database_path(const std::filesystem::path& data_dir);

class SqliteStore final : public PersonalData {
 public:
  // Opens or creates the file and migrates it. Throws sql::CorruptDatabase or
  // std::runtime_error naming the file (see the top of this header).
  explicit SqliteStore(StoreOptions options);
  ~SqliteStore() override;
  SqliteStore(const SqliteStore&) = delete;
  SqliteStore& operator=(const SqliteStore&) = delete;

  const std::filesystem::path& path() const { return path_; }

  // --- PersonalData -------------------------------------------------------------
  // add_reminder validates the reminder (recurrence.h), computes next_fire_utc_ms when it
  // is 0 and ignores `id` and `state` (a new reminder is active).
  std::int64_t add_reminder(const Reminder& reminder) override;
  std::vector<Reminder> reminders_between(std::int64_t from_utc_ms,
                                          std::int64_t to_utc_ms) override;
  std::vector<Reminder> list_reminders() override;
  std::optional<Reminder> get_reminder(std::int64_t id) override;
  bool remove_reminder(std::int64_t id) override;
  bool snooze_reminder(std::int64_t id, std::int64_t until_utc_ms) override;
  bool complete_reminder(std::int64_t id) override;

  std::int64_t add_contact(const Contact& contact) override;
  std::vector<Contact> find_contacts(std::string_view name_or_alias) override;
  std::vector<Contact> list_contacts() override;
  bool remove_contact(std::int64_t id) override;
  // Replaces every field of contact `contact.id` (`marvin contacts edit`). Throws naming
  // the field when one is malformed, before anything changes; false when there is no
  // contact with that id.
  bool update_contact(const Contact& contact);

  std::vector<Person> list_people() override;

  std::optional<std::string> storage_get(std::string_view skill_id, std::string_view key) override;
  void storage_set(std::string_view skill_id, std::string_view key,
                   std::string_view value) override;
  bool storage_remove(std::string_view skill_id, std::string_view key) override;

  void log_event(std::string_view kind, std::string_view source,
                 std::string_view message) override;

  // --- for the scheduler --------------------------------------------------------
  // The active reminder that fires first (ties: lowest id), via the (state, next fire)
  // index: O(log n).
  std::optional<Reminder> next_due_reminder();
  // Active reminders with next_fire_utc_ms <= at_utc_ms, soonest first.
  std::vector<Reminder> due_reminders(std::int64_t at_utc_ms);
  // Records that the occurrence `fired_utc_ms` of reminder `id` was handled: the reminder
  // fires next at `next_utc_ms`, or becomes done if nullopt. Applies only if the reminder
  // is still active with next_fire_utc_ms == `expected_next_utc_ms` (so a snooze or a
  // cancel that raced with firing wins); returns whether it applied. `event`, if not
  // empty, is logged in the same transaction.
  bool advance_reminder(std::int64_t id, std::int64_t expected_next_utc_ms,
                        std::int64_t fired_utc_ms, std::optional<std::int64_t> next_utc_ms,
                        std::string_view event_kind = {}, std::string_view event_message = {});
  // Several advance_reminder calls in one transaction (one fsync): the scheduler retires
  // the reminders missed during downtime this way. Returns how many applied.
  struct Advance {
    std::int64_t id;
    std::int64_t expected_next_utc_ms;
    std::int64_t fired_utc_ms;
    std::optional<std::int64_t> next_utc_ms;
    std::string event_kind;
    std::string event_message;
  };
  std::size_t advance_reminders(const std::vector<Advance>& advances);

  // --- smart-home device aliases ("the big lamp" -> "living room lamp") -------------
  // Alias (compared without case) -> the device's name or id. Setting an existing alias
  // replaces its device. Empty alias or device: std::invalid_argument, nothing stored.
  void set_device_alias(std::string_view alias, std::string_view device);
  bool remove_device_alias(std::string_view alias);  // false if there was none
  std::vector<std::pair<std::string, std::string>> device_aliases();  // by alias

  // --- people and faces ---------------------------------------------------------
  std::int64_t add_person(const Person& person);
  // Removes the person and their embeddings; false if there was none.
  bool remove_person(std::int64_t id);
  // Gives person `id` another name (their embeddings stay); false if there is none. An empty
  // name: std::runtime_error naming the field, nothing changed.
  bool rename_person(std::int64_t id, std::string_view name);
  std::int64_t add_face_embedding(std::int64_t person_id, std::string_view model_id,
                                  std::span<const float> values);
  // All embeddings, or those of one person.
  std::vector<FaceEmbedding> face_embeddings(std::optional<std::int64_t> person_id = {});

  // --- sightings (finding, issue 22) -------------------------------------------------
  // Records that `s.what` was seen now (the store's clock stamps it, replacing what was
  // recorded for it before). Empty what/room or a kind other than person/object:
  // std::invalid_argument, nothing stored.
  void record_sighting(const Sighting& s);
  // Sightings seen at or after `since_utc_ms`, newest first; `what` empty: all.
  std::vector<Sighting> sightings(std::string_view what, std::int64_t since_utc_ms = 0);

  // --- event log ----------------------------------------------------------------
  // The latest `limit` events, newest first.
  std::vector<Event> recent_events(std::size_t limit);
  // The event with this id, if there is one.
  std::optional<Event> event(std::int64_t id);
  // Notified after every commit that added events (log_event, advance_reminder(s) with an
  // event), on the writing thread: the web page shows new events at once, without reading
  // the log on a timer. Events written by other processes are not notified here.
  ChangeSignal& events_written() { return events_written_; }

  // --- backup ---------------------------------------------------------------------
  // Everything (all reminders in every state, contacts, people, faces, storage, events,
  // sightings) as one JSON document; binary values are base64.
  nlohmann::json export_json();
  // Replaces all personal data with the backup `doc`, keeping its ids. The document is
  // validated first; on any error (message names `source` and the JSON field) nothing
  // changes.
  void import_json(const nlohmann::json& doc, std::string_view source = "backup");
  // Number of rows in reminders, contacts, people, storage, events and sightings together.
  std::int64_t row_count();

 private:
  std::int64_t now() const;

  std::filesystem::path path_;
  std::string path_text_;
  const Clock* clock_;
  std::mutex mutex_;
  sqlite3* db_ = nullptr;
  ChangeSignal events_written_;
};

}  // namespace marvin::data
