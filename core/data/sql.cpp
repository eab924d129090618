#include "data/sql.h"

namespace marvin::data::sql {

void fail(sqlite3* db, int code, const std::string& path, std::string_view doing) {
  const int primary = code & 0xff;
  std::string message = db ? sqlite3_errmsg(db) : sqlite3_errstr(code);
  if (primary == SQLITE_NOTADB || primary == SQLITE_CORRUPT) {
    throw CorruptDatabase("database " + path + " is corrupted or not a Marvin database (" +
                          message + ", while " + std::string(doing) +
                          "); the file was left untouched for recovery: restore a backup "
                          "with `marvin data import` into a new data directory");
  }
  throw std::runtime_error("database " + path + ": " + message + " (while " +
                           std::string(doing) + ")");
}

void exec(sqlite3* db, const std::string& path, const char* text) {
  const int rc = sqlite3_exec(db, text, nullptr, nullptr, nullptr);
  if (rc != SQLITE_OK) fail(db, rc, path, text);
}

Statement::Statement(sqlite3* db, const std::string& path, std::string_view text)
    : db_(db), path_(path) {
  const int rc = sqlite3_prepare_v2(db, text.data(), static_cast<int>(text.size()), &stmt_, nullptr);
  if (rc != SQLITE_OK) fail(db, rc, path, text);
}

Statement::~Statement() { sqlite3_finalize(stmt_); }

Statement& Statement::bind(int index, std::int64_t value) {
  const int rc = sqlite3_bind_int64(stmt_, index, value);
  if (rc != SQLITE_OK) fail(db_, rc, path_, sqlite3_sql(stmt_));
  return *this;
}

Statement& Statement::bind(int index, std::string_view text) {
  const int rc = sqlite3_bind_text64(stmt_, index, text.data(), text.size(), SQLITE_TRANSIENT,
                                     SQLITE_UTF8);
  if (rc != SQLITE_OK) fail(db_, rc, path_, sqlite3_sql(stmt_));
  return *this;
}

Statement& Statement::bind_blob(int index, std::span<const std::byte> bytes) {
  // A zero-length blob must still be a blob, not NULL: give SQLite a valid pointer.
  static const std::byte kEmpty{};
  const int rc = sqlite3_bind_blob64(stmt_, index, bytes.empty() ? &kEmpty : bytes.data(),
                                     bytes.size(), SQLITE_TRANSIENT);
  if (rc != SQLITE_OK) fail(db_, rc, path_, sqlite3_sql(stmt_));
  return *this;
}

Statement& Statement::bind_null(int index) {
  const int rc = sqlite3_bind_null(stmt_, index);
  if (rc != SQLITE_OK) fail(db_, rc, path_, sqlite3_sql(stmt_));
  return *this;
}

bool Statement::step() {
  const int rc = sqlite3_step(stmt_);
  if (rc == SQLITE_ROW) return true;
  if (rc == SQLITE_DONE) return false;
  fail(db_, rc, path_, sqlite3_sql(stmt_));
}

void Statement::reset() {
  sqlite3_reset(stmt_);
  sqlite3_clear_bindings(stmt_);
}

std::int64_t Statement::int64(int column) const { return sqlite3_column_int64(stmt_, column); }

bool Statement::is_null(int column) const {
  return sqlite3_column_type(stmt_, column) == SQLITE_NULL;
}

std::string Statement::text(int column) const {
  const unsigned char* p = sqlite3_column_text(stmt_, column);
  const int n = sqlite3_column_bytes(stmt_, column);
  return p ? std::string(reinterpret_cast<const char*>(p), static_cast<std::size_t>(n)) : std::string();
}

std::string Statement::blob(int column) const {
  const void* p = sqlite3_column_blob(stmt_, column);
  const int n = sqlite3_column_bytes(stmt_, column);
  return p ? std::string(static_cast<const char*>(p), static_cast<std::size_t>(n)) : std::string();
}

Transaction::Transaction(sqlite3* db, const std::string& path) : db_(db), path_(path) {
  exec(db_, path_, "BEGIN IMMEDIATE");
}

Transaction::~Transaction() {
  if (!done_) sqlite3_exec(db_, "ROLLBACK", nullptr, nullptr, nullptr);
}

void Transaction::commit() {
  exec(db_, path_, "COMMIT");
  done_ = true;
}

std::int64_t pragma_int(sqlite3* db, const std::string& path, const char* pragma) {
  Statement s(db, path, std::string("PRAGMA ") + pragma);
  if (!s.step()) throw std::runtime_error("database " + path + ": PRAGMA " + pragma + " returned no row");
  return s.int64(0);
}

}  // namespace marvin::data::sql
