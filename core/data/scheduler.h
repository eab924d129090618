// Scheduler: makes reminders fire on time on the host's event loop.
//
// One boost::asio::steady_timer on the given io_context waits for the reminder that is
// due first (SqliteStore::next_due_reminder, an index lookup), so thousands of stored
// reminders cost one timer while idle. The wait is capped (max_timer_wait_ms, default
// 60 s) so a wall-clock change (NTP after boot) is noticed within that time.
//
// When a reminder is due, `on_fire` is called with it (the host speaks it through the
// skill manager), then its next occurrence is committed (recurrence.h) or, for a one-off
// reminder, it becomes done. Calling back first and committing after means a crash in
// between repeats the reminder at the next start rather than losing it.
//
// Late reminders, the same rule at start-up and at run time (suspend, clock jumps):
//   due less than on_time_ms ago           fires normally (missed = false)
//   due within missed_grace_ms             fires once with missed = true: "you missed ..."
//   older                                  not spoken: listed in the StartupReport (and
//                                          the event log, kind "reminder_missed")
// A recurring reminder missed several times fires (or is listed) once, for its latest
// missed occurrence, then goes on with its next future occurrence.
//
// Threading: start(), fire_due() and the timer run on the io_context's thread;
// reminders_changed(), snooze() and done() may be called from any thread (they post to
// the io_context). The store must outlive the scheduler; destroying the scheduler
// cancels its timer.
#pragma once

#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <vector>

#include "data/clock.h"
#include "data/sqlite_store.h"

namespace marvin::data {

struct SchedulerOptions {
  std::int64_t on_time_ms = 60 * 1000;
  std::int64_t missed_grace_ms = 30 * 60 * 1000;
  std::int64_t max_timer_wait_ms = 60 * 1000;
};

struct Firing {
  Reminder reminder;        // as stored when it became due
  std::int64_t due_utc_ms;  // the occurrence being announced
  bool missed = false;      // it was due a while ago: say "you missed ..."
};

struct MissedReminder {
  Reminder reminder;
  std::int64_t first_missed_utc_ms;  // the oldest occurrence not announced
  std::int64_t last_missed_utc_ms;   // the newest one
};

struct StartupReport {
  std::vector<Firing> fired;           // announced through on_fire (missed or on time)
  std::vector<MissedReminder> listed;  // too old to announce
};

class Scheduler {
 public:
  using FireCallback = std::function<void(const Firing&)>;

  // Nothing happens until start(). `store`, `clock` and `io` must outlive the scheduler.
  Scheduler(boost::asio::io_context& io, SqliteStore& store, const Clock& clock,
            FireCallback on_fire, SchedulerOptions options = {});
  ~Scheduler();
  Scheduler(const Scheduler&) = delete;
  Scheduler& operator=(const Scheduler&) = delete;

  // Catches up with what became due while the host was off (see above), then arms the
  // timer. Returns what was announced and what was only listed.
  StartupReport start();

  // Announces and advances everything due at the clock's now, then re-arms. The timer
  // calls it; calling it directly is harmless.
  StartupReport fire_due();

  // Re-reads the next due reminder and re-arms the timer (posted to the io_context).
  // Call after adding, removing or editing reminders.
  void reminders_changed();

  // "Snooze": fires again `minutes` from now. False if there is no such reminder.
  bool snooze(std::int64_t id, std::int64_t minutes);
  // "Done": see SqliteStore::complete_reminder.
  bool done(std::int64_t id);

  // The instant the timer is armed for (the next due reminder's next_fire_utc_ms), or
  // nullopt when nothing is scheduled. For tests and `marvin schedule list`.
  std::optional<std::int64_t> armed_for() const { return armed_for_; }

 private:
  void arm();

  boost::asio::io_context& io_;
  SqliteStore& store_;
  const Clock& clock_;
  FireCallback on_fire_;
  SchedulerOptions options_;
  boost::asio::steady_timer timer_;
  std::optional<std::int64_t> armed_for_;
  std::shared_ptr<int> alive_ = std::make_shared<int>(0);
};

}  // namespace marvin::data
