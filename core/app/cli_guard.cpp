// `marvin guard status|off`: guard mode (issue 22) from the command line. The guard runs in
// the `marvin run` process; it keeps its state in the data directory's SQLite store
// (skills/guard.h: kGuardStorageId) at every change, and `off` leaves a request there that
// the running guard reads before its next look (within a second). Without a running host the
// stored state is changed directly, so a guard left "on" by a process that ended can be
// cleared. `marvin run --in-memory` shares no state: these commands cannot reach it.
#include <chrono>
#include <ctime>
#include <memory>
#include <string>

#include "app/cli.h"
#include "data/sqlite_store.h"
#include "skills/guard.h"

namespace marvin::app {
namespace {

struct GuardArgs {
  std::string data_dir;
  void add_data_dir(CLI::App& cmd) {
    cmd.add_option("--data-dir", data_dir,
                   "Directory holding marvin.db (default: $MARVIN_DATA_DIR, "
                   "$XDG_DATA_HOME/marvin, ~/.local/share/marvin)");
  }
  std::filesystem::path db() const {
    return data::database_path(data_dir.empty() ? data::default_data_dir()
                                                : std::filesystem::path(data_dir));
  }
};

// The stored state; nullopt when guard mode was never turned on with this data directory.
std::optional<skills::GuardState> guard_stored_state(data::SqliteStore& store) {
  auto text = store.storage_get(skills::kGuardStorageId, skills::kGuardStateKey);
  if (!text) return std::nullopt;
  try {
    return skills::guard_state_from_json(*text);
  } catch (const std::invalid_argument& e) {
    throw CliError(store.path().string() + ": " + e.what());
  }
}

std::string guard_utc(std::int64_t unix_ms) {
  const std::time_t t = static_cast<std::time_t>(unix_ms / 1000);
  std::tm tm{};
  gmtime_r(&t, &tm);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%d %H:%M UTC", &tm);
  return text;
}

void guard_status(const GuardArgs& a) {
  data::StoreOptions o;
  o.path = a.db();
  data::SqliteStore store(o);
  const auto s = guard_stored_state(store);
  if (!s) return write_line("guard mode: off (never turned on)");
  if (s->on) {
    return write_line("guard mode: on since " + guard_utc(s->since_ms) + ", " +
                      std::to_string(s->alerts) + (s->alerts == 1 ? " alert" : " alerts"));
  }
  write_line("guard mode: off" +
             (s->by.empty() ? std::string() : " (turned off by " + s->by + ")") + ", " +
             std::to_string(s->alerts) + (s->alerts == 1 ? " alert" : " alerts") +
             " in the last watch");
}

void guard_off(const GuardArgs& a) {
  data::StoreOptions o;
  o.path = a.db();
  data::SqliteStore store(o);
  auto s = guard_stored_state(store);
  if (!s || !s->on) return write_line("guard mode is already off; nothing changed");
  // The request names this watch: a guard turned on again later is not ended by it.
  store.storage_set(skills::kGuardStorageId, skills::kGuardOffKey, std::to_string(s->since_ms));
  s->on = false;
  s->by = skills::kOffByCommandLine;
  store.storage_set(skills::kGuardStorageId, skills::kGuardStateKey, skills::guard_state_json(*s));
  write_line("guard mode: off (a running Marvin stops watching before its next look)");
}

void install_guard(CLI::App& root) {
  CLI::App& guard = command_group(root, "guard", "Guard mode: is it on, turn it off");
  {
    auto a = std::make_shared<GuardArgs>();
    auto* cmd = guard.add_subcommand("status", "Whether guard mode is on, since when, alerts");
    a->add_data_dir(*cmd);
    cmd->callback([a] { guard_status(*a); });
  }
  {
    auto a = std::make_shared<GuardArgs>();
    auto* cmd = guard.add_subcommand("off", "Turn guard mode off (the running Marvin's too)");
    a->add_data_dir(*cmd);
    cmd->callback([a] { guard_off(*a); });
  }
}

}  // namespace

MARVIN_CLI_COMMANDS(install_guard);

}  // namespace marvin::app
