#include "data/scheduler.h"

#include <boost/asio/post.hpp>
#include <chrono>

#include "common/log.h"
#include "data/recurrence.h"

namespace marvin::data {

Scheduler::Scheduler(boost::asio::io_context& io, SqliteStore& store, const Clock& clock,
                     FireCallback on_fire, SchedulerOptions options)
    : io_(io),
      store_(store),
      clock_(clock),
      on_fire_(std::move(on_fire)),
      options_(options),
      timer_(io) {}

Scheduler::~Scheduler() {
  alive_.reset();
  timer_.cancel();
}

StartupReport Scheduler::start() { return fire_due(); }

StartupReport Scheduler::fire_due() {
  StartupReport report;
  const std::int64_t now = clock_.now_utc_ms();
  std::vector<SqliteStore::Advance> listed;
  for (const Reminder& r : store_.due_reminders(now)) {
    // A snooze may have put next_fire between occurrences: the latest missed instant is
    // whichever is later.
    std::int64_t latest = r.next_fire_utc_ms;
    std::optional<std::int64_t> next;
    try {
      if (auto last = last_occurrence_at_or_before(r, now); last && *last > latest) latest = *last;
      next = next_occurrence(r, std::max(latest, now));
    } catch (const std::exception& e) {
      // A reminder the store holds but cannot schedule (a time zone that vanished from
      // tzdata): retire it, loudly, instead of firing it forever.
      log(LogLevel::kError, "data", "reminder " + std::to_string(r.id) + ": " + e.what());
      store_.advance_reminder(r.id, r.next_fire_utc_ms, now, std::nullopt, "reminder_error",
                              "reminder " + std::to_string(r.id) + " '" + r.title + "': " + e.what());
      continue;
    }
    const std::int64_t late = now - latest;
    if (late <= options_.missed_grace_ms) {
      Firing firing{r, latest, late > options_.on_time_ms};
      try {
        on_fire_(firing);
      } catch (const std::exception& e) {
        log(LogLevel::kError, "data", "announcing reminder " + std::to_string(r.id) + ": " + e.what());
      }
      store_.advance_reminder(r.id, r.next_fire_utc_ms, latest, next);
      report.fired.push_back(std::move(firing));
    } else {
      listed.push_back({r.id, r.next_fire_utc_ms, latest, next, "reminder_missed",
                        "missed reminder " + std::to_string(r.id) + " '" + r.title + "' due " +
                            format_local(latest, r.time_zone)});
      report.listed.push_back({r, r.next_fire_utc_ms, latest});
    }
  }
  // Retired together, one commit: after a long downtime there may be many. A crash before
  // this commit lists them again at the next start.
  store_.advance_reminders(listed);
  arm();
  return report;
}

void Scheduler::arm() {
  const std::optional<Reminder> next = store_.next_due_reminder();
  if (!next) {
    armed_for_.reset();
    timer_.cancel();
    return;
  }
  armed_for_ = next->next_fire_utc_ms;
  const std::int64_t wait =
      std::clamp<std::int64_t>(*armed_for_ - clock_.now_utc_ms(), 0, options_.max_timer_wait_ms);
  timer_.expires_after(std::chrono::milliseconds(wait));  // cancels a pending wait
  timer_.async_wait([this, alive = std::weak_ptr<int>(alive_)](const boost::system::error_code& ec) {
    if (ec || alive.expired()) return;
    if (armed_for_ && clock_.now_utc_ms() >= *armed_for_) {
      fire_due();
    } else {
      arm();  // the wait was capped, or the clock moved: look again
    }
  });
}

void Scheduler::reminders_changed() {
  boost::asio::post(io_, [this, alive = std::weak_ptr<int>(alive_)] {
    if (!alive.expired()) arm();
  });
}

bool Scheduler::snooze(std::int64_t id, std::int64_t minutes) {
  const bool ok = store_.snooze_reminder(id, clock_.now_utc_ms() + minutes * 60 * 1000);
  if (ok) reminders_changed();
  return ok;
}

bool Scheduler::done(std::int64_t id) {
  const bool ok = store_.complete_reminder(id);
  if (ok) reminders_changed();
  return ok;
}

}  // namespace marvin::data
