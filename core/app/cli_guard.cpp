// `marvin guard status|off`: guard mode (issue 22) from the command line. The guard runs in
// the `marvin run` process; it keeps its state in the data directory's SQLite store
// (skills/guard.h: kGuardStorageId) at every change, and `off` leaves a request there that
// the running guard reads before its next look (within a second). Without a running host the
// stored state is changed directly, so a guard left "on" by a process that ended can be
// cleared. `marvin run --in-memory` shares no state: these commands cannot reach it.
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <memory>
#include <string>

#include "app/cli.h"
#include "app/guard_schedule.h"
#include "data/recurrence.h"
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
  const std::string pictures =
      s->pictures > 0 ? ", " + std::to_string(s->pictures) + " looks saw only pictures (a TV)" : "";
  if (s->on) {
    return write_line("guard mode: on since " + guard_utc(s->since_ms) + ", " +
                      std::to_string(s->alerts) + (s->alerts == 1 ? " alert" : " alerts") +
                      pictures);
  }
  write_line("guard mode: off" +
             (s->by.empty() ? std::string() : " (turned off by " + s->by + ")") + ", " +
             std::to_string(s->alerts) + (s->alerts == 1 ? " alert" : " alerts") +
             " in the last watch" + pictures);
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

std::string guard_zone(const std::string& given) {
  if (!given.empty()) return given;
  if (const char* tz = std::getenv("TZ"); tz && *tz) return *tz == ':' ? tz + 1 : tz;
  std::error_code ec;
  const auto target = std::filesystem::read_symlink("/etc/localtime", ec);
  const std::string text = target.string();
  const auto at = text.find("zoneinfo/");
  return ec || at == std::string::npos ? "UTC" : text.substr(at + 9);
}

void print_guard_schedule(const data::Reminder& r) {
  const bool on = guard_switch(r).value_or(false);
  std::printf("%lld  %s  next %s (%s)\n", static_cast<long long>(r.id), on ? "on " : "off",
              data::format_local(r.next_fire_utc_ms, r.time_zone).c_str(),
              r.title.substr(std::string(on ? kGuardOnTitle : kGuardOffTitle).size()).c_str());
}

// `marvin guard schedule add WHEN [--tz ZONE]`: the plan's reminders (guard_schedule.h).
// Bad input: the parser's message, exit 2, nothing stored.
void guard_schedule_add(const GuardArgs& a, const std::string& when, const std::string& tz) {
  std::vector<data::Reminder> reminders;
  try {
    reminders = guard_plan_reminders(parse_guard_plan(when), guard_zone(tz),
                                     data::SystemClock::instance().now_utc_ms());
  } catch (const std::exception& e) {
    throw CliError(std::string("guard schedule: ") + e.what(), 2);
  }
  data::StoreOptions o;
  o.path = a.db();
  data::SqliteStore store(o);
  for (const data::Reminder& r : reminders)
    print_guard_schedule(*store.get_reminder(store.add_reminder(r)));
  std::printf("(a running Marvin follows it from its next minute)\n");
}

void guard_schedule_list(const GuardArgs& a) {
  data::StoreOptions o;
  o.path = a.db();
  data::SqliteStore store(o);
  int n = 0;
  for (const data::Reminder& r : store.list_reminders()) {
    if (!guard_switch(r)) continue;
    print_guard_schedule(r);
    ++n;
  }
  if (n == 0) std::printf("no guard schedule\n");
}

// Cancels the reminder `id` and, for a window, its other end (same "when").
void guard_schedule_cancel(const GuardArgs& a, std::int64_t id) {
  data::StoreOptions o;
  o.path = a.db();
  data::SqliteStore store(o);
  const auto r = store.get_reminder(id);
  if (!r || !guard_switch(*r) || r->state != data::Reminder::State::kActive) {
    throw CliError("guard schedule: no guard schedule with id " + std::to_string(id) +
                   " (see `marvin guard schedule list`)");
  }
  const bool on = *guard_switch(*r);
  const std::string when = r->title.substr(std::string(on ? kGuardOnTitle : kGuardOffTitle).size());
  for (const data::Reminder& other : store.list_reminders()) {
    if (other.id != id && guard_switch(other) &&
        other.title == (on ? kGuardOffTitle : kGuardOnTitle) + when) {
      store.remove_reminder(other.id);
    }
  }
  store.remove_reminder(id);
  std::printf("cancelled the guard schedule '%s'\n", when.c_str());
}

void install_guard(CLI::App& root) {
  CLI::App& guard = command_group(root, "guard", "Guard mode: is it on, turn it off, schedules");
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
  CLI::App* schedule = guard.add_subcommand(
      "schedule", "Guard mode by schedule: add \"every night at 10 pm\", list, cancel ID");
  schedule->require_subcommand(1);
  {
    auto a = std::make_shared<GuardArgs>();
    auto when = std::make_shared<std::string>();
    auto tz = std::make_shared<std::string>();
    auto* cmd = schedule->add_subcommand(
        "add", "Add a schedule: \"every night at 10 pm\", \"on weekdays from 9 to 5\"");
    cmd->add_option("WHEN", *when, "When guard mode comes on (and, with from/to, goes off)")
        ->required();
    cmd->add_option("--tz", *tz, "IANA time zone (default: $TZ or the system's)");
    a->add_data_dir(*cmd);
    cmd->callback([a, when, tz] { guard_schedule_add(*a, *when, *tz); });
  }
  {
    auto a = std::make_shared<GuardArgs>();
    auto* cmd = schedule->add_subcommand("list", "The guard schedules, soonest first");
    a->add_data_dir(*cmd);
    cmd->callback([a] { guard_schedule_list(*a); });
  }
  {
    auto a = std::make_shared<GuardArgs>();
    auto id = std::make_shared<std::int64_t>(0);
    auto* cmd = schedule->add_subcommand("cancel", "Cancel a guard schedule (both of its ends)");
    cmd->add_option("ID", *id, "Its id (see `marvin guard schedule list`)")->required();
    a->add_data_dir(*cmd);
    cmd->callback([a, id] { guard_schedule_cancel(*a, *id); });
  }
}

}  // namespace

MARVIN_CLI_COMMANDS(install_guard);

}  // namespace marvin::app
