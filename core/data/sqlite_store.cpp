#include "data/sqlite_store.h"

#include <sqlite3.h>

#include <algorithm>
#include <array>
#include <functional>
#include <limits>
#include <type_traits>
#include <cctype>
#include <cstdlib>
#include <cstring>
#include <nlohmann/json.hpp>
#include <set>

#include "data/migrations.h"
#include "data/recurrence.h"
#include "data/sql.h"

namespace marvin::data {
namespace {

using nlohmann::json;
using sql::Statement;
using sql::Transaction;

constexpr const char* kReminderColumns =
    "id, title, first_fire_utc_ms, time_zone, recurrence_kind, weekdays, interval_minutes, "
    "window_start_minute, window_end_minute, next_fire_utc_ms, created_by, state";

Reminder read_reminder(const Statement& s) {
  Reminder r;
  r.id = s.int64(0);
  r.title = s.text(1);
  r.first_fire_utc_ms = s.int64(2);
  r.time_zone = s.text(3);
  r.recurrence.kind = static_cast<Recurrence::Kind>(s.int64(4));
  r.recurrence.weekdays = static_cast<std::uint8_t>(s.int64(5));
  r.recurrence.interval_minutes = static_cast<std::int32_t>(s.int64(6));
  r.recurrence.window_start_minute = static_cast<std::int32_t>(s.int64(7));
  r.recurrence.window_end_minute = static_cast<std::int32_t>(s.int64(8));
  r.next_fire_utc_ms = s.int64(9);
  r.created_by = s.text(10);
  r.state = static_cast<Reminder::State>(s.int64(11));
  return r;
}

std::string lower_ascii(std::string_view text) {
  std::string out(text);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

void validate_contact(const Contact& c) {
  if (c.name.empty()) throw std::runtime_error("name: a contact needs a name");
  for (const std::string& number : c.phone_numbers) {
    const bool ok = !number.empty() && std::all_of(number.begin(), number.end(), [](char ch) {
      return std::isdigit(static_cast<unsigned char>(ch)) || std::strchr("+-()/ .", ch);
    });
    if (!ok || std::none_of(number.begin(), number.end(), [](char ch) {
          return std::isdigit(static_cast<unsigned char>(ch));
        }))
      throw std::runtime_error("phone_numbers: '" + number +
                               "' is not a phone number (digits, spaces and + - ( ) / . only)");
  }
  for (const std::string& alias : c.aliases)
    if (alias.empty()) throw std::runtime_error("aliases: an alias may not be empty");
  for (const std::string& uri : c.sip_uris) {
    const auto at = uri.find('@');
    if (uri.rfind("sip:", 0) != 0 || at == std::string::npos || at == 4 || at + 1 == uri.size() ||
        uri.find_first_of(" \t\r\n<>\";") != std::string::npos)
      throw std::runtime_error("sip_uris: '" + uri +
                               "' is not a SIP address (expected sip:user@host)");
  }
  if (c.emergency_order < 0)
    throw std::runtime_error("emergency_order: must be 0 (none) or 1, 2, ... (the order), got " +
                             std::to_string(c.emergency_order));
}

void check_skill_key(std::string_view skill_id, std::string_view key) {
  if (skill_id.empty()) throw std::runtime_error("skill_id: storage needs a skill id");
  if (key.empty()) throw std::runtime_error("key: storage keys may not be empty");
}

// --- base64 (backup files carry binary values) ------------------------------------
constexpr char kB64[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";

std::string to_base64(std::string_view in) {
  std::string out;
  out.reserve((in.size() + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 2 < in.size(); i += 3) {
    const auto n = (std::uint32_t{static_cast<unsigned char>(in[i])} << 16) |
                   (std::uint32_t{static_cast<unsigned char>(in[i + 1])} << 8) |
                   std::uint32_t{static_cast<unsigned char>(in[i + 2])};
    for (int k = 18; k >= 0; k -= 6) out += kB64[(n >> k) & 63u];
  }
  if (i < in.size()) {
    std::uint32_t n = std::uint32_t{static_cast<unsigned char>(in[i])} << 16;
    if (i + 1 < in.size()) n |= std::uint32_t{static_cast<unsigned char>(in[i + 1])} << 8;
    out += kB64[(n >> 18) & 63u];
    out += kB64[(n >> 12) & 63u];
    out += i + 1 < in.size() ? kB64[(n >> 6) & 63u] : '=';
    out += '=';
  }
  return out;
}

std::string from_base64(std::string_view in, const std::string& field) {
  if (in.size() % 4 != 0) throw std::runtime_error(field + ": not base64 (length)");
  std::string out;
  out.reserve(in.size() / 4 * 3);
  for (std::size_t i = 0; i < in.size(); i += 4) {
    std::uint32_t n = 0;
    int pad = 0;
    for (std::size_t k = 0; k < 4; ++k) {
      const char c = in[i + k];
      std::uint32_t v = 0;
      if (c == '=' && i + 4 == in.size() && k >= 2) {
        ++pad;
      } else if (pad > 0) {
        throw std::runtime_error(field + ": not base64 (data after padding)");
      } else if (const char* p = std::strchr(kB64, c); p && c != '\0') {
        v = static_cast<std::uint32_t>(p - kB64);
      } else {
        throw std::runtime_error(field + ": not base64 (character " + std::to_string(i + k) + ")");
      }
      n = (n << 6) | v;
    }
    out += static_cast<char>((n >> 16) & 0xffu);
    if (pad < 2) out += static_cast<char>((n >> 8) & 0xffu);
    if (pad < 1) out += static_cast<char>(n & 0xffu);
  }
  return out;
}

std::span<const std::byte> bytes_of(std::string_view s) {
  return std::as_bytes(std::span<const char>(s.data(), s.size()));
}

const char* state_name(Reminder::State s) {
  switch (s) {
    case Reminder::State::kActive: return "active";
    case Reminder::State::kDone: return "done";
    case Reminder::State::kCancelled: return "cancelled";
  }
  return "?";
}

const char* kind_name(Recurrence::Kind k) {
  switch (k) {
    case Recurrence::Kind::kOnce: return "once";
    case Recurrence::Kind::kDaily: return "daily";
    case Recurrence::Kind::kWeekdays: return "weekdays";
    case Recurrence::Kind::kWeekly: return "weekly";
    case Recurrence::Kind::kInterval: return "interval";
  }
  return "?";
}

}  // namespace

std::filesystem::path default_data_dir() {
  if (const char* dir = std::getenv("MARVIN_DATA_DIR"); dir && *dir) return dir;
  if (const char* xdg = std::getenv("XDG_DATA_HOME"); xdg && *xdg)
    return std::filesystem::path(xdg) / "marvin";
  if (const char* home = std::getenv("HOME"); home && *home)
    return std::filesystem::path(home) / ".local" / "share" / "marvin";
  throw std::runtime_error(
      "no data directory: set MARVIN_DATA_DIR, XDG_DATA_HOME or HOME (or pass --data-dir)");
}

std::filesystem::path database_path(const std::filesystem::path& data_dir) {
  return data_dir / "marvin.db";
}

SqliteStore::SqliteStore(StoreOptions options)
    : path_(std::move(options.path)),
      path_text_(path_.string()),
      clock_(options.clock ? options.clock : &SystemClock::instance()) {
  if (path_.empty()) throw std::runtime_error("database path is empty");
  if (path_.has_parent_path()) {
    std::error_code ec;
    std::filesystem::create_directories(path_.parent_path(), ec);
    if (ec)
      throw std::runtime_error("cannot create data directory " + path_.parent_path().string() +
                               ": " + ec.message());
  }
  const int rc = sqlite3_open_v2(path_text_.c_str(), &db_,
                                 SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE | SQLITE_OPEN_NOMUTEX,
                                 nullptr);
  try {
    if (rc != SQLITE_OK) sql::fail(db_, rc, path_text_, "opening");
    sqlite3_extended_result_codes(db_, 1);
    sqlite3_busy_timeout(db_, options.busy_timeout_ms);
    // Reading the header first: a file that is not a database fails here, before
    // anything could write to it.
    const std::int64_t version = sql::pragma_int(db_, path_text_, "user_version");
    if (options.verify_on_open) {
      Statement check(db_, path_text_, "PRAGMA quick_check(1)");
      const std::string verdict = check.step() ? check.text(0) : std::string("no result");
      if (verdict != "ok")
        throw sql::CorruptDatabase("database " + path_text_ + " is corrupted (" + verdict +
                                   "); the file was left untouched for recovery: restore a "
                                   "backup with `marvin data import` into a new data directory");
    }
    const std::int64_t app_id = sql::pragma_int(db_, path_text_, "application_id");
    if (app_id != 0 && app_id != kApplicationId)
      throw std::runtime_error("database " + path_text_ +
                               " belongs to another application (application_id " +
                               std::to_string(app_id) + "); it was not changed");
    if (version == 0) {
      Statement tables(db_, path_text_, "SELECT count(*) FROM sqlite_schema");
      tables.step();
      if (tables.int64(0) != 0)
        throw std::runtime_error("database " + path_text_ +
                                 " is an SQLite file with tables but no Marvin schema version; "
                                 "it was not changed");
    }
    if (version > kSchemaVersion)
      throw std::runtime_error("database " + path_text_ + " has schema version " +
                               std::to_string(version) + ", newer than this Marvin understands (" +
                               std::to_string(kSchemaVersion) +
                               "); upgrade Marvin or use another data directory. The file was "
                               "not changed");
    {
      Statement wal(db_, path_text_, "PRAGMA journal_mode = WAL");
      const std::string mode = wal.step() ? wal.text(0) : std::string();
      if (mode != "wal")
        throw std::runtime_error("database " + path_text_ + ": cannot switch to WAL mode (got '" +
                                 mode + "')");
    }
    sql::exec(db_, path_text_,
              options.synchronous == StoreOptions::Sync::kFull ? "PRAGMA synchronous = FULL"
                                                               : "PRAGMA synchronous = OFF");
    sql::exec(db_, path_text_, "PRAGMA foreign_keys = ON");
    migrate(db_, path_text_, static_cast<int>(version), kSchemaVersion);
  } catch (...) {
    sqlite3_close_v2(db_);
    db_ = nullptr;
    throw;
  }
}

SqliteStore::~SqliteStore() { sqlite3_close_v2(db_); }

std::int64_t SqliteStore::now() const { return clock_->now_utc_ms(); }

// --- reminders --------------------------------------------------------------------

std::int64_t SqliteStore::add_reminder(const Reminder& in) {
  validate_reminder(in);
  std::int64_t next = in.next_fire_utc_ms;
  if (next == 0) {
    const auto first = next_occurrence(in, in.first_fire_utc_ms - 1);
    if (!first) throw std::runtime_error("recurrence: the reminder never fires");
    next = *first;
  }
  std::lock_guard lock(mutex_);
  Statement s(db_, path_text_,
              "INSERT INTO reminders(title, first_fire_utc_ms, time_zone, recurrence_kind, "
              "weekdays, interval_minutes, window_start_minute, window_end_minute, "
              "next_fire_utc_ms, created_by, state, created_utc_ms) "
              "VALUES(?,?,?,?,?,?,?,?,?,?,0,?)");
  s.bind(1, in.title)
      .bind(2, in.first_fire_utc_ms)
      .bind(3, in.time_zone)
      .bind(4, std::int64_t{static_cast<int>(in.recurrence.kind)})
      .bind(5, std::int64_t{in.recurrence.weekdays})
      .bind(6, std::int64_t{in.recurrence.interval_minutes})
      .bind(7, std::int64_t{in.recurrence.window_start_minute})
      .bind(8, std::int64_t{in.recurrence.window_end_minute})
      .bind(9, next)
      .bind(10, in.created_by)
      .bind(11, now());
  s.run();  // autocommit: durable when it returns
  return sqlite3_last_insert_rowid(db_);
}

std::vector<Reminder> SqliteStore::reminders_between(std::int64_t from, std::int64_t to) {
  std::lock_guard lock(mutex_);
  Statement s(db_, path_text_,
              std::string("SELECT ") + kReminderColumns +
                  " FROM reminders WHERE state = 0 AND next_fire_utc_ms >= ? AND "
                  "next_fire_utc_ms < ? ORDER BY next_fire_utc_ms, id");
  s.bind(1, from).bind(2, to);
  std::vector<Reminder> out;
  while (s.step()) out.push_back(read_reminder(s));
  return out;
}

std::vector<Reminder> SqliteStore::list_reminders() {
  std::lock_guard lock(mutex_);
  Statement s(db_, path_text_,
              std::string("SELECT ") + kReminderColumns +
                  " FROM reminders WHERE state = 0 ORDER BY next_fire_utc_ms, id");
  std::vector<Reminder> out;
  while (s.step()) out.push_back(read_reminder(s));
  return out;
}

std::optional<Reminder> SqliteStore::get_reminder(std::int64_t id) {
  std::lock_guard lock(mutex_);
  Statement s(db_, path_text_,
              std::string("SELECT ") + kReminderColumns + " FROM reminders WHERE id = ?");
  s.bind(1, id);
  if (!s.step()) return std::nullopt;
  return read_reminder(s);
}

bool SqliteStore::remove_reminder(std::int64_t id) {
  std::lock_guard lock(mutex_);
  Statement s(db_, path_text_, "UPDATE reminders SET state = 2 WHERE id = ? AND state = 0");
  s.bind(1, id).run();
  return sqlite3_changes(db_) > 0;
}

bool SqliteStore::snooze_reminder(std::int64_t id, std::int64_t until_utc_ms) {
  std::lock_guard lock(mutex_);
  Statement s(db_, path_text_,
              "UPDATE reminders SET state = 0, next_fire_utc_ms = ? WHERE id = ? AND state IN (0, 1)");
  s.bind(1, until_utc_ms).bind(2, id).run();
  return sqlite3_changes(db_) > 0;
}

bool SqliteStore::complete_reminder(std::int64_t id) {
  std::lock_guard lock(mutex_);
  Transaction tx(db_, path_text_);
  // A reminder that already fired and retired (state 1) is acknowledged too: "I took them"
  // after a one-off pill reminder belongs in the log as much as after a daily one.
  Statement get(db_, path_text_,
                "SELECT recurrence_kind, title, state FROM reminders "
                "WHERE id = ? AND state IN (0, 1)");
  get.bind(1, id);
  if (!get.step()) return false;
  const bool once = get.int64(0) == static_cast<int>(Recurrence::Kind::kOnce);
  const std::string title = get.text(1);
  if (once && get.int64(2) == 0) {
    Statement s(db_, path_text_, "UPDATE reminders SET state = 1 WHERE id = ?");
    s.bind(1, id).run();
  }
  Statement ev(db_, path_text_,
               "INSERT INTO events(time_utc_ms, kind, source, message) VALUES(?, 'reminder_done', "
               "'scheduler', ?)");
  ev.bind(1, now()).bind(2, "reminder " + std::to_string(id) + " '" + title + "' done").run();
  tx.commit();
  return true;
}

std::optional<Reminder> SqliteStore::next_due_reminder() {
  std::lock_guard lock(mutex_);
  Statement s(db_, path_text_,
              std::string("SELECT ") + kReminderColumns +
                  " FROM reminders WHERE state = 0 ORDER BY next_fire_utc_ms, id LIMIT 1");
  if (!s.step()) return std::nullopt;
  return read_reminder(s);
}

std::vector<Reminder> SqliteStore::due_reminders(std::int64_t at_utc_ms) {
  std::lock_guard lock(mutex_);
  Statement s(db_, path_text_,
              std::string("SELECT ") + kReminderColumns +
                  " FROM reminders WHERE state = 0 AND next_fire_utc_ms <= ? "
                  "ORDER BY next_fire_utc_ms, id");
  s.bind(1, at_utc_ms);
  std::vector<Reminder> out;
  while (s.step()) out.push_back(read_reminder(s));
  return out;
}

bool SqliteStore::advance_reminder(std::int64_t id, std::int64_t expected_next,
                                   std::int64_t fired_utc_ms, std::optional<std::int64_t> next,
                                   std::string_view event_kind, std::string_view event_message) {
  return advance_reminders({Advance{id, expected_next, fired_utc_ms, next, std::string(event_kind),
                                    std::string(event_message)}}) == 1;
}

std::size_t SqliteStore::advance_reminders(const std::vector<Advance>& advances) {
  if (advances.empty()) return 0;
  bool logged = false;
  std::size_t applied = 0;
  {
    std::lock_guard lock(mutex_);
    Transaction tx(db_, path_text_);
    Statement s(db_, path_text_,
                "UPDATE reminders SET next_fire_utc_ms = ?, state = ?, last_fired_utc_ms = ? "
                "WHERE id = ? AND state = 0 AND next_fire_utc_ms = ?");
    Statement ev(db_, path_text_,
                 "INSERT INTO events(time_utc_ms, kind, source, message) VALUES(?, ?, 'scheduler', ?)");
    for (const Advance& a : advances) {
      s.reset();
      s.bind(1, a.next_utc_ms.value_or(a.expected_next_utc_ms))
          .bind(2, std::int64_t{a.next_utc_ms ? 0 : 1})
          .bind(3, a.fired_utc_ms)
          .bind(4, a.id)
          .bind(5, a.expected_next_utc_ms)
          .run();
      if (sqlite3_changes(db_) == 0) continue;
      ++applied;
      if (!a.event_kind.empty()) {
        ev.reset();
        ev.bind(1, now()).bind(2, a.event_kind).bind(3, a.event_message).run();
        logged = true;
      }
    }
    tx.commit();
  }
  if (logged) events_written_.notify();  // outside the lock: a watcher may read the log
  return applied;
}

// --- contacts and people ------------------------------------------------------------

namespace {

void insert_contact_lists(sqlite3* db, const std::string& path, std::int64_t id,
                          const Contact& c) {
  Statement alias(db, path, "INSERT INTO contact_aliases(contact_id, position, alias) VALUES(?,?,?)");
  for (std::size_t i = 0; i < c.aliases.size(); ++i) {
    alias.reset();
    alias.bind(1, id).bind(2, static_cast<std::int64_t>(i)).bind(3, c.aliases[i]).run();
  }
  Statement phone(db, path, "INSERT INTO contact_phones(contact_id, position, number) VALUES(?,?,?)");
  for (std::size_t i = 0; i < c.phone_numbers.size(); ++i) {
    phone.reset();
    phone.bind(1, id).bind(2, static_cast<std::int64_t>(i)).bind(3, c.phone_numbers[i]).run();
  }
  Statement sip(db, path, "INSERT INTO contact_sip_uris(contact_id, position, uri) VALUES(?,?,?)");
  for (std::size_t i = 0; i < c.sip_uris.size(); ++i) {
    sip.reset();
    sip.bind(1, id).bind(2, static_cast<std::int64_t>(i)).bind(3, c.sip_uris[i]).run();
  }
}

std::vector<Contact> load_contacts(sqlite3* db, const std::string& path, const char* where,
                                   const std::function<void(Statement&)>& bind = {}) {
  std::vector<Contact> out;
  Statement s(db, path,
              std::string("SELECT id, name, relation, emergency_order FROM contacts ") + where);
  if (bind) bind(s);
  while (s.step()) {
    Contact c;
    c.id = s.int64(0);
    c.name = s.text(1);
    c.relation = s.text(2);
    c.emergency_order = static_cast<int>(s.int64(3));
    out.push_back(std::move(c));
  }
  Statement alias(db, path, "SELECT alias FROM contact_aliases WHERE contact_id = ? ORDER BY position");
  Statement phone(db, path, "SELECT number FROM contact_phones WHERE contact_id = ? ORDER BY position");
  Statement sip(db, path, "SELECT uri FROM contact_sip_uris WHERE contact_id = ? ORDER BY position");
  for (Contact& c : out) {
    alias.reset();
    alias.bind(1, c.id);
    while (alias.step()) c.aliases.push_back(alias.text(0));
    phone.reset();
    phone.bind(1, c.id);
    while (phone.step()) c.phone_numbers.push_back(phone.text(0));
    sip.reset();
    sip.bind(1, c.id);
    while (sip.step()) c.sip_uris.push_back(sip.text(0));
  }
  return out;
}

}  // namespace

std::int64_t SqliteStore::add_contact(const Contact& c) {
  validate_contact(c);
  std::lock_guard lock(mutex_);
  Transaction tx(db_, path_text_);
  Statement s(db_, path_text_,
              "INSERT INTO contacts(name, relation, emergency_order) VALUES(?, ?, ?)");
  s.bind(1, c.name).bind(2, c.relation).bind(3, std::int64_t{c.emergency_order}).run();
  const std::int64_t id = sqlite3_last_insert_rowid(db_);
  insert_contact_lists(db_, path_text_, id, c);
  tx.commit();
  return id;
}

std::vector<Contact> SqliteStore::find_contacts(std::string_view name_or_alias) {
  const std::string folded = lower_ascii(name_or_alias);
  if (folded.empty()) return {};
  std::lock_guard lock(mutex_);
  // The full name, an alias, one word of the name ("Anna" finds "Anna Schmidt") or the
  // relation ("my daughter"): exact matches first. Case folding is ASCII (SQLite's lower()
  // without ICU).
  return load_contacts(
      db_, path_text_,
      "WHERE lower(name) = ?1 OR id IN (SELECT contact_id FROM contact_aliases WHERE "
      "lower(alias) = ?2) OR (' ' || lower(name) || ' ') LIKE ('% ' || ?3 || ' %') ESCAPE '\\' "
      "OR (relation <> '' AND (lower(relation) = ?1 OR 'my ' || lower(relation) = ?1)) "
      "ORDER BY lower(name) <> ?1, name, id",
      [&](Statement& s) {
        std::string pattern;
        for (char c : folded) {
          if (c == '%' || c == '_' || c == '\\') pattern += '\\';
          pattern += c;
        }
        s.bind(1, folded).bind(2, folded).bind(3, pattern);
      });
}

std::vector<Contact> SqliteStore::list_contacts() {
  std::lock_guard lock(mutex_);
  return load_contacts(db_, path_text_, "ORDER BY name, id");
}

bool SqliteStore::update_contact(const Contact& c) {
  validate_contact(c);
  std::lock_guard lock(mutex_);
  Transaction tx(db_, path_text_);
  Statement s(db_, path_text_,
              "UPDATE contacts SET name = ?, relation = ?, emergency_order = ? WHERE id = ?");
  s.bind(1, c.name).bind(2, c.relation).bind(3, std::int64_t{c.emergency_order}).bind(4, c.id).run();
  if (sqlite3_changes(db_) == 0) return false;  // the transaction rolls back
  for (const char* table : {"contact_aliases", "contact_phones", "contact_sip_uris"}) {
    Statement d(db_, path_text_, std::string("DELETE FROM ") + table + " WHERE contact_id = ?");
    d.bind(1, c.id).run();
  }
  insert_contact_lists(db_, path_text_, c.id, c);
  tx.commit();
  return true;
}

bool SqliteStore::remove_contact(std::int64_t id) {
  std::lock_guard lock(mutex_);
  Statement s(db_, path_text_, "DELETE FROM contacts WHERE id = ?");
  s.bind(1, id).run();
  return sqlite3_changes(db_) > 0;
}

std::vector<Person> SqliteStore::list_people() {
  std::lock_guard lock(mutex_);
  Statement s(db_, path_text_, "SELECT id, name, contact_id FROM people ORDER BY name, id");
  std::vector<Person> out;
  while (s.step()) {
    Person p;
    p.id = s.int64(0);
    p.name = s.text(1);
    if (!s.is_null(2)) p.contact_id = s.int64(2);
    out.push_back(std::move(p));
  }
  return out;
}

std::int64_t SqliteStore::add_person(const Person& p) {
  if (p.name.empty()) throw std::runtime_error("name: a person needs a name");
  std::lock_guard lock(mutex_);
  Statement s(db_, path_text_, "INSERT INTO people(name, contact_id) VALUES(?, ?)");
  s.bind(1, p.name).bind(2, p.contact_id);
  try {
    s.run();
  } catch (const std::runtime_error&) {
    if (p.contact_id && (sqlite3_extended_errcode(db_) == SQLITE_CONSTRAINT_FOREIGNKEY))
      throw std::runtime_error("contact_id: there is no contact " + std::to_string(*p.contact_id));
    throw;
  }
  return sqlite3_last_insert_rowid(db_);
}

bool SqliteStore::remove_person(std::int64_t id) {
  std::lock_guard lock(mutex_);
  Statement s(db_, path_text_, "DELETE FROM people WHERE id = ?");
  s.bind(1, id).run();
  return sqlite3_changes(db_) > 0;
}

bool SqliteStore::rename_person(std::int64_t id, std::string_view name) {
  if (name.empty()) throw std::runtime_error("name: a person needs a name");
  std::lock_guard lock(mutex_);
  Statement s(db_, path_text_, "UPDATE people SET name = ? WHERE id = ?");
  s.bind(1, name).bind(2, id).run();
  return sqlite3_changes(db_) > 0;
}

std::int64_t SqliteStore::add_face_embedding(std::int64_t person_id, std::string_view model_id,
                                             std::span<const float> values) {
  if (model_id.empty()) throw std::runtime_error("model_id: a face embedding needs its model id");
  if (values.empty()) throw std::runtime_error("values: a face embedding may not be empty");
  std::lock_guard lock(mutex_);
  Statement s(db_, path_text_,
              "INSERT INTO face_embeddings(person_id, model_id, dimension, data) VALUES(?,?,?,?)");
  s.bind(1, person_id)
      .bind(2, model_id)
      .bind(3, static_cast<std::int64_t>(values.size()))
      .bind_blob(4, std::as_bytes(values));
  try {
    s.run();
  } catch (const std::runtime_error&) {
    if (sqlite3_extended_errcode(db_) == SQLITE_CONSTRAINT_FOREIGNKEY)
      throw std::runtime_error("person_id: there is no person " + std::to_string(person_id));
    throw;
  }
  return sqlite3_last_insert_rowid(db_);
}

std::vector<FaceEmbedding> SqliteStore::face_embeddings(std::optional<std::int64_t> person_id) {
  std::lock_guard lock(mutex_);
  Statement s(db_, path_text_,
              "SELECT id, person_id, model_id, dimension, data FROM face_embeddings "
              "WHERE ?1 IS NULL OR person_id = ?1 ORDER BY id");
  s.bind(1, person_id);
  std::vector<FaceEmbedding> out;
  while (s.step()) {
    FaceEmbedding f;
    f.id = s.int64(0);
    f.person_id = s.int64(1);
    f.model_id = s.text(2);
    const std::string data = s.blob(4);
    f.values.resize(static_cast<std::size_t>(s.int64(3)));
    std::memcpy(f.values.data(), data.data(), std::min(data.size(), f.values.size() * sizeof(float)));
    out.push_back(std::move(f));
  }
  return out;
}

// --- per-skill storage and events ------------------------------------------------

std::optional<std::string> SqliteStore::storage_get(std::string_view skill_id, std::string_view key) {
  check_skill_key(skill_id, key);
  std::lock_guard lock(mutex_);
  Statement s(db_, path_text_, "SELECT value FROM skill_storage WHERE skill_id = ? AND key = ?");
  s.bind(1, skill_id).bind(2, key);
  if (!s.step()) return std::nullopt;
  return s.blob(0);
}

void SqliteStore::storage_set(std::string_view skill_id, std::string_view key, std::string_view value) {
  check_skill_key(skill_id, key);
  std::lock_guard lock(mutex_);
  Statement s(db_, path_text_,
              "INSERT INTO skill_storage(skill_id, key, value) VALUES(?,?,?) "
              "ON CONFLICT(skill_id, key) DO UPDATE SET value = excluded.value");
  s.bind(1, skill_id).bind(2, key).bind_blob(3, bytes_of(value)).run();
}

bool SqliteStore::storage_remove(std::string_view skill_id, std::string_view key) {
  check_skill_key(skill_id, key);
  std::lock_guard lock(mutex_);
  Statement s(db_, path_text_, "DELETE FROM skill_storage WHERE skill_id = ? AND key = ?");
  s.bind(1, skill_id).bind(2, key).run();
  return sqlite3_changes(db_) > 0;
}

void SqliteStore::set_device_alias(std::string_view alias, std::string_view device) {
  if (alias.empty()) throw std::invalid_argument("alias: a device alias must not be empty");
  if (device.empty()) throw std::invalid_argument("device: name the device the alias means");
  std::lock_guard lock(mutex_);
  Statement s(db_, path_text_,
              "INSERT INTO device_aliases(alias, device) VALUES(?,?) "
              "ON CONFLICT(alias) DO UPDATE SET device = excluded.device");
  s.bind(1, alias).bind(2, device).run();
}

bool SqliteStore::remove_device_alias(std::string_view alias) {
  std::lock_guard lock(mutex_);
  Statement s(db_, path_text_, "DELETE FROM device_aliases WHERE alias = ?");
  s.bind(1, alias).run();
  return sqlite3_changes(db_) > 0;
}

std::vector<std::pair<std::string, std::string>> SqliteStore::device_aliases() {
  std::lock_guard lock(mutex_);
  Statement s(db_, path_text_, "SELECT alias, device FROM device_aliases ORDER BY alias");
  std::vector<std::pair<std::string, std::string>> out;
  while (s.step()) out.emplace_back(s.text(0), s.text(1));
  return out;
}

void SqliteStore::log_event(std::string_view kind, std::string_view source, std::string_view message) {
  if (kind.empty()) throw std::runtime_error("kind: an event needs a kind");
  {
    std::lock_guard lock(mutex_);
    Statement s(db_, path_text_,
                "INSERT INTO events(time_utc_ms, kind, source, message) VALUES(?,?,?,?)");
    s.bind(1, now()).bind(2, kind).bind(3, source).bind(4, message).run();
  }
  events_written_.notify();  // outside the lock: a watcher may read the log
}

void SqliteStore::record_sighting(const Sighting& g) {
  if (g.what.empty()) throw std::invalid_argument("sighting: 'what' is empty");
  if (g.kind != "person" && g.kind != "object") {
    throw std::invalid_argument("sighting of " + g.what + ": kind is '" + g.kind +
                                "', expected person or object");
  }
  std::lock_guard lock(mutex_);
  Statement s(db_, path_text_,
              "INSERT OR REPLACE INTO sightings(what, kind, room, near, seen_utc_ms) "
              "VALUES(?,?,?,?,?)");
  s.bind(1, g.what).bind(2, g.kind).bind(3, g.room).bind(4, g.near).bind(5, now()).run();
}

std::vector<Sighting> SqliteStore::sightings(std::string_view what, std::int64_t since_utc_ms) {
  std::lock_guard lock(mutex_);
  Statement s(db_, path_text_,
              "SELECT what, kind, room, near, seen_utc_ms FROM sightings "
              "WHERE (?1 = '' OR what = ?1) AND seen_utc_ms >= ?2 ORDER BY seen_utc_ms DESC");
  s.bind(1, what).bind(2, since_utc_ms);
  std::vector<Sighting> out;
  while (s.step()) out.push_back({s.text(0), s.text(1), s.text(2), s.text(3), s.int64(4)});
  return out;
}

std::vector<Event> SqliteStore::recent_events(std::size_t limit) {
  std::lock_guard lock(mutex_);
  Statement s(db_, path_text_,
              "SELECT id, time_utc_ms, kind, source, message FROM events ORDER BY id DESC LIMIT ?");
  s.bind(1, static_cast<std::int64_t>(limit));
  std::vector<Event> out;
  while (s.step()) out.push_back({s.int64(0), s.int64(1), s.text(2), s.text(3), s.text(4)});
  return out;
}

std::optional<Event> SqliteStore::event(std::int64_t id) {
  std::lock_guard lock(mutex_);
  Statement s(db_, path_text_,
              "SELECT id, time_utc_ms, kind, source, message FROM events WHERE id = ?");
  s.bind(1, id);
  if (!s.step()) return std::nullopt;
  return Event{s.int64(0), s.int64(1), s.text(2), s.text(3), s.text(4)};
}

std::int64_t SqliteStore::row_count() {
  std::lock_guard lock(mutex_);
  Statement s(db_, path_text_,
              "SELECT (SELECT count(*) FROM reminders) + (SELECT count(*) FROM contacts) + "
              "(SELECT count(*) FROM people) + (SELECT count(*) FROM skill_storage) + "
              "(SELECT count(*) FROM events) + (SELECT count(*) FROM sightings)");
  s.step();
  return s.int64(0);
}

// --- backup --------------------------------------------------------------------------

json SqliteStore::export_json() {
  json doc = {{"format", "marvin-personal-data"}, {"version", 1}, {"schema_version", kSchemaVersion}};
  std::lock_guard lock(mutex_);
  // One read transaction: a consistent snapshot even while the host writes.
  sql::exec(db_, path_text_, "BEGIN");
  struct End {
    sqlite3* db;
    ~End() { sqlite3_exec(db, "COMMIT", nullptr, nullptr, nullptr); }
  } end{db_};
  json reminders = json::array();
  {
    Statement s(db_, path_text_, std::string("SELECT ") + kReminderColumns + " FROM reminders ORDER BY id");
    while (s.step()) {
      const Reminder r = read_reminder(s);
      reminders.push_back({{"id", r.id},
                           {"title", r.title},
                           {"first_fire_utc_ms", r.first_fire_utc_ms},
                           {"time_zone", r.time_zone},
                           {"recurrence",
                            {{"kind", kind_name(r.recurrence.kind)},
                             {"weekdays", r.recurrence.weekdays},
                             {"interval_minutes", r.recurrence.interval_minutes},
                             {"window_start_minute", r.recurrence.window_start_minute},
                             {"window_end_minute", r.recurrence.window_end_minute}}},
                           {"next_fire_utc_ms", r.next_fire_utc_ms},
                           {"created_by", r.created_by},
                           {"state", state_name(r.state)}});
    }
  }
  doc["reminders"] = std::move(reminders);
  json contacts = json::array();
  for (const Contact& c : load_contacts(db_, path_text_, "ORDER BY id"))
    contacts.push_back({{"id", c.id},
                        {"name", c.name},
                        {"aliases", c.aliases},
                        {"relation", c.relation},
                        {"phone_numbers", c.phone_numbers},
                        {"sip_uris", c.sip_uris},
                        {"emergency_order", c.emergency_order}});
  doc["contacts"] = std::move(contacts);
  json people = json::array();
  {
    Statement s(db_, path_text_, "SELECT id, name, contact_id FROM people ORDER BY id");
    Statement f(db_, path_text_,
                "SELECT model_id, dimension, data FROM face_embeddings WHERE person_id = ? ORDER BY id");
    while (s.step()) {
      json p = {{"id", s.int64(0)}, {"name", s.text(1)}, {"contact_id", nullptr}};
      if (!s.is_null(2)) p["contact_id"] = s.int64(2);
      json faces = json::array();
      f.reset();
      f.bind(1, s.int64(0));
      while (f.step())
        faces.push_back({{"model_id", f.text(0)}, {"dimension", f.int64(1)}, {"data", to_base64(f.blob(2))}});
      p["faces"] = std::move(faces);
      people.push_back(std::move(p));
    }
  }
  doc["people"] = std::move(people);
  json storage = json::array();
  {
    Statement s(db_, path_text_, "SELECT skill_id, key, value FROM skill_storage ORDER BY skill_id, key");
    while (s.step())
      storage.push_back({{"skill_id", s.text(0)}, {"key", s.text(1)}, {"value", to_base64(s.blob(2))}});
  }
  doc["storage"] = std::move(storage);
  json events = json::array();
  {
    Statement s(db_, path_text_, "SELECT id, time_utc_ms, kind, source, message FROM events ORDER BY id");
    while (s.step())
      events.push_back({{"id", s.int64(0)},
                        {"time_utc_ms", s.int64(1)},
                        {"kind", s.text(2)},
                        {"source", s.text(3)},
                        {"message", s.text(4)}});
  }
  doc["events"] = std::move(events);
  json sightings = json::array();
  {
    Statement s(db_, path_text_,
                "SELECT what, kind, room, near, seen_utc_ms FROM sightings ORDER BY kind, what");
    while (s.step())
      sightings.push_back({{"what", s.text(0)},
                           {"kind", s.text(1)},
                           {"room", s.text(2)},
                           {"near", s.text(3)},
                           {"seen_utc_ms", s.int64(4)}});
  }
  doc["sightings"] = std::move(sightings);
  return doc;
}

namespace {

// Reads field `key` of object `obj` as T, naming "source: path.key" on any mismatch.
template <class T>
T field(const json& obj, const char* key, const std::string& where) {
  const std::string name = where + "." + key;
  if (!obj.is_object()) throw std::runtime_error(where + ": expected an object");
  const auto it = obj.find(key);
  if (it == obj.end()) throw std::runtime_error(name + ": missing");
  try {
    if constexpr (std::is_integral_v<T>) {
      if (!it->is_number_integer()) throw std::runtime_error("expected an integer");
      const auto v = it->get<std::int64_t>();
      if (v < std::numeric_limits<T>::min() || v > std::numeric_limits<T>::max())
        throw std::runtime_error("out of range");
      return static_cast<T>(v);
    } else if constexpr (std::is_same_v<T, std::string>) {
      if (!it->is_string()) throw std::runtime_error("expected a string");
      return it->get<std::string>();
    } else {
      std::vector<std::string> out;
      if (!it->is_array()) throw std::runtime_error("expected an array of strings");
      for (const json& e : *it) {
        if (!e.is_string()) throw std::runtime_error("expected an array of strings");
        out.push_back(e.get<std::string>());
      }
      return out;
    }
  } catch (const std::runtime_error& e) {
    throw std::runtime_error(name + ": " + e.what());
  }
}

const json& array_field(const json& doc, const char* key, const std::string& where) {
  const auto it = doc.find(key);
  if (it == doc.end() || !it->is_array())
    throw std::runtime_error(where + "." + key + ": expected an array");
  return *it;
}

template <class Names>
int enum_index(const std::string& value, const Names& names, const std::string& where) {
  for (std::size_t i = 0; i < std::size(names); ++i)
    if (value == names[i]) return static_cast<int>(i);
  std::string expected;
  for (const char* n : names) {
    if (!expected.empty()) expected += ", ";
    expected += n;
  }
  throw std::runtime_error(where + ": unknown value '" + value + "' (expected " + expected + ")");
}

}  // namespace

void SqliteStore::import_json(const json& doc, std::string_view source_view) {
  const std::string src(source_view);
  // 1. Parse and validate everything before touching the database.
  if (!doc.is_object() || doc.value("format", std::string()) != "marvin-personal-data")
    throw std::runtime_error(src + ": format: expected \"marvin-personal-data\"");
  if (field<int>(doc, "version", src) != 1)
    throw std::runtime_error(src + ".version: unsupported backup version " + doc["version"].dump() +
                             " (expected 1)");
  struct Face {
    std::string model;
    std::int64_t dimension;
    std::string data;
  };
  struct PersonIn {
    Person person;
    std::vector<Face> faces;
  };
  std::vector<Reminder> reminders;
  std::vector<Contact> contacts;
  std::vector<PersonIn> people;
  std::vector<std::array<std::string, 3>> storage;
  std::vector<Event> events;
  std::set<std::int64_t> reminder_ids, contact_ids, person_ids, event_ids;
  std::set<std::pair<std::string, std::string>> storage_keys;
  static constexpr const char* kKinds[] = {"once", "daily", "weekdays", "weekly", "interval"};
  static constexpr const char* kStates[] = {"active", "done", "cancelled"};

  const json& jr = array_field(doc, "reminders", src);
  for (std::size_t i = 0; i < jr.size(); ++i) {
    const std::string w = src + ".reminders[" + std::to_string(i) + "]";
    const json& e = jr[i];
    Reminder r;
    r.id = field<std::int64_t>(e, "id", w);
    r.title = field<std::string>(e, "title", w);
    r.first_fire_utc_ms = field<std::int64_t>(e, "first_fire_utc_ms", w);
    r.time_zone = field<std::string>(e, "time_zone", w);
    const std::string rw = w + ".recurrence";
    const json& rec = e.contains("recurrence") ? e["recurrence"] : json();
    r.recurrence.kind = static_cast<Recurrence::Kind>(
        enum_index(field<std::string>(rec, "kind", rw), kKinds, rw + ".kind"));
    r.recurrence.weekdays = field<std::uint8_t>(rec, "weekdays", rw);
    r.recurrence.interval_minutes = field<std::int32_t>(rec, "interval_minutes", rw);
    r.recurrence.window_start_minute = field<std::int32_t>(rec, "window_start_minute", rw);
    r.recurrence.window_end_minute = field<std::int32_t>(rec, "window_end_minute", rw);
    r.next_fire_utc_ms = field<std::int64_t>(e, "next_fire_utc_ms", w);
    r.created_by = field<std::string>(e, "created_by", w);
    r.state = static_cast<Reminder::State>(
        enum_index(field<std::string>(e, "state", w), kStates, w + ".state"));
    try {
      validate_reminder(r);
    } catch (const std::exception& ex) {
      throw std::runtime_error(w + "." + ex.what());
    }
    if (!reminder_ids.insert(r.id).second) throw std::runtime_error(w + ".id: duplicate id " + std::to_string(r.id));
    reminders.push_back(std::move(r));
  }
  const json& jc = array_field(doc, "contacts", src);
  for (std::size_t i = 0; i < jc.size(); ++i) {
    const std::string w = src + ".contacts[" + std::to_string(i) + "]";
    Contact c;
    c.id = field<std::int64_t>(jc[i], "id", w);
    c.name = field<std::string>(jc[i], "name", w);
    c.aliases = field<std::vector<std::string>>(jc[i], "aliases", w);
    c.relation = field<std::string>(jc[i], "relation", w);
    c.phone_numbers = field<std::vector<std::string>>(jc[i], "phone_numbers", w);
    // Backups from before schema 4 have neither.
    if (jc[i].contains("sip_uris"))
      c.sip_uris = field<std::vector<std::string>>(jc[i], "sip_uris", w);
    if (jc[i].contains("emergency_order"))
      c.emergency_order = field<int>(jc[i], "emergency_order", w);
    try {
      validate_contact(c);
    } catch (const std::exception& ex) {
      throw std::runtime_error(w + "." + ex.what());
    }
    if (!contact_ids.insert(c.id).second) throw std::runtime_error(w + ".id: duplicate id " + std::to_string(c.id));
    contacts.push_back(std::move(c));
  }
  const json& jp = array_field(doc, "people", src);
  for (std::size_t i = 0; i < jp.size(); ++i) {
    const std::string w = src + ".people[" + std::to_string(i) + "]";
    PersonIn p;
    p.person.id = field<std::int64_t>(jp[i], "id", w);
    p.person.name = field<std::string>(jp[i], "name", w);
    if (p.person.name.empty()) throw std::runtime_error(w + ".name: a person needs a name");
    if (jp[i].contains("contact_id") && !jp[i]["contact_id"].is_null()) {
      p.person.contact_id = field<std::int64_t>(jp[i], "contact_id", w);
      if (!contact_ids.count(*p.person.contact_id))
        throw std::runtime_error(w + ".contact_id: there is no contact " +
                                 std::to_string(*p.person.contact_id) + " in the backup");
    }
    const json& jf = array_field(jp[i], "faces", w);
    for (std::size_t k = 0; k < jf.size(); ++k) {
      const std::string fw = w + ".faces[" + std::to_string(k) + "]";
      Face f{field<std::string>(jf[k], "model_id", fw), field<std::int64_t>(jf[k], "dimension", fw), {}};
      f.data = from_base64(field<std::string>(jf[k], "data", fw), fw + ".data");
      if (f.model.empty()) throw std::runtime_error(fw + ".model_id: empty");
      if (f.dimension <= 0 || static_cast<std::size_t>(f.dimension) * sizeof(float) != f.data.size())
        throw std::runtime_error(fw + ".data: " + std::to_string(f.data.size()) +
                                 " bytes do not hold dimension " + std::to_string(f.dimension) +
                                 " floats");
      p.faces.push_back(std::move(f));
    }
    if (!person_ids.insert(p.person.id).second) throw std::runtime_error(w + ".id: duplicate id " + std::to_string(p.person.id));
    people.push_back(std::move(p));
  }
  const json& js = array_field(doc, "storage", src);
  for (std::size_t i = 0; i < js.size(); ++i) {
    const std::string w = src + ".storage[" + std::to_string(i) + "]";
    std::array<std::string, 3> kv{field<std::string>(js[i], "skill_id", w),
                                  field<std::string>(js[i], "key", w), {}};
    kv[2] = from_base64(field<std::string>(js[i], "value", w), w + ".value");
    try {
      check_skill_key(kv[0], kv[1]);
    } catch (const std::exception& ex) {
      throw std::runtime_error(w + "." + ex.what());
    }
    if (!storage_keys.insert({kv[0], kv[1]}).second)
      throw std::runtime_error(w + ": duplicate key '" + kv[1] + "' of skill '" + kv[0] + "'");
    storage.push_back(std::move(kv));
  }
  const json& je = array_field(doc, "events", src);
  for (std::size_t i = 0; i < je.size(); ++i) {
    const std::string w = src + ".events[" + std::to_string(i) + "]";
    Event e{field<std::int64_t>(je[i], "id", w), field<std::int64_t>(je[i], "time_utc_ms", w),
            field<std::string>(je[i], "kind", w), field<std::string>(je[i], "source", w),
            field<std::string>(je[i], "message", w)};
    if (!event_ids.insert(e.id).second) throw std::runtime_error(w + ".id: duplicate id " + std::to_string(e.id));
    events.push_back(std::move(e));
  }
  // Backups from before schema 6 (finding) have no sightings: the import then clears them,
  // as it replaces everything else.
  std::vector<Sighting> sightings;
  std::set<std::pair<std::string, std::string>> sighting_keys;
  if (doc.contains("sightings")) {
    const json& jg = array_field(doc, "sightings", src);
    for (std::size_t i = 0; i < jg.size(); ++i) {
      const std::string w = src + ".sightings[" + std::to_string(i) + "]";
      Sighting g{field<std::string>(jg[i], "what", w), field<std::string>(jg[i], "kind", w),
                 field<std::string>(jg[i], "room", w), field<std::string>(jg[i], "near", w),
                 field<std::int64_t>(jg[i], "seen_utc_ms", w)};
      if (g.what.empty()) throw std::runtime_error(w + ".what: empty (expected a name or a thing)");
      if (g.kind != "person" && g.kind != "object")
        throw std::runtime_error(w + ".kind: unknown value '" + g.kind +
                                 "' (expected person, object)");
      std::string key = g.what;  // the table compares names case-insensitively
      for (char& c : key) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
      if (!sighting_keys.insert({key, g.kind}).second)
        throw std::runtime_error(w + ": duplicate sighting of " + g.kind + " '" + g.what + "'");
      sightings.push_back(std::move(g));
    }
  }

  // 2. Replace everything in one transaction.
  std::lock_guard lock(mutex_);
  Transaction tx(db_, path_text_);
  sql::exec(db_, path_text_,
            "DELETE FROM face_embeddings; DELETE FROM people; DELETE FROM contact_aliases; "
            "DELETE FROM contact_phones; DELETE FROM contact_sip_uris; DELETE FROM contacts; DELETE FROM reminders; "
            "DELETE FROM skill_storage; DELETE FROM events; DELETE FROM sightings;");
  {
    Statement s(db_, path_text_,
                "INSERT INTO reminders(id, title, first_fire_utc_ms, time_zone, recurrence_kind, "
                "weekdays, interval_minutes, window_start_minute, window_end_minute, "
                "next_fire_utc_ms, created_by, state, created_utc_ms) VALUES(?,?,?,?,?,?,?,?,?,?,?,?,?)");
    const std::int64_t stamp = now();
    for (const Reminder& r : reminders) {
      s.reset();
      s.bind(1, r.id).bind(2, r.title).bind(3, r.first_fire_utc_ms).bind(4, r.time_zone)
          .bind(5, std::int64_t{static_cast<int>(r.recurrence.kind)})
          .bind(6, std::int64_t{r.recurrence.weekdays})
          .bind(7, std::int64_t{r.recurrence.interval_minutes})
          .bind(8, std::int64_t{r.recurrence.window_start_minute})
          .bind(9, std::int64_t{r.recurrence.window_end_minute})
          .bind(10, r.next_fire_utc_ms).bind(11, r.created_by)
          .bind(12, std::int64_t{static_cast<int>(r.state)}).bind(13, stamp).run();
    }
  }
  {
    Statement s(db_, path_text_,
                "INSERT INTO contacts(id, name, relation, emergency_order) VALUES(?,?,?,?)");
    for (const Contact& c : contacts) {
      s.reset();
      s.bind(1, c.id).bind(2, c.name).bind(3, c.relation).bind(4, std::int64_t{c.emergency_order}).run();
      insert_contact_lists(db_, path_text_, c.id, c);
    }
  }
  {
    Statement s(db_, path_text_, "INSERT INTO people(id, name, contact_id) VALUES(?,?,?)");
    Statement f(db_, path_text_,
                "INSERT INTO face_embeddings(person_id, model_id, dimension, data) VALUES(?,?,?,?)");
    for (const PersonIn& p : people) {
      s.reset();
      s.bind(1, p.person.id).bind(2, p.person.name).bind(3, p.person.contact_id).run();
      for (const Face& face : p.faces) {
        f.reset();
        f.bind(1, p.person.id).bind(2, face.model).bind(3, face.dimension).bind_blob(4, bytes_of(face.data)).run();
      }
    }
  }
  {
    Statement s(db_, path_text_, "INSERT INTO skill_storage(skill_id, key, value) VALUES(?,?,?)");
    for (const auto& kv : storage) {
      s.reset();
      s.bind(1, kv[0]).bind(2, kv[1]).bind_blob(3, bytes_of(kv[2])).run();
    }
  }
  {
    Statement s(db_, path_text_,
                "INSERT INTO events(id, time_utc_ms, kind, source, message) VALUES(?,?,?,?,?)");
    for (const Event& e : events) {
      s.reset();
      s.bind(1, e.id).bind(2, e.time_utc_ms).bind(3, e.kind).bind(4, e.source).bind(5, e.message).run();
    }
  }
  {
    Statement s(db_, path_text_,
                "INSERT INTO sightings(what, kind, room, near, seen_utc_ms) VALUES(?,?,?,?,?)");
    for (const Sighting& g : sightings) {
      s.reset();
      s.bind(1, g.what).bind(2, g.kind).bind(3, g.room).bind(4, g.near).bind(5, g.seen_utc_ms).run();
    }
  }
  tx.commit();
}

}  // namespace marvin::data
