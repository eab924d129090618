// Scheduler: one Asio timer, on-time firing, snooze/done, catching up after downtime.
// A ManualClock drives "now"; the io_context is only polled, never run with a real wait.
#include <doctest/doctest.h>

#include <boost/asio/io_context.hpp>

#include "data/recurrence.h"
#include "data/scheduler.h"
#include "test_support.h"

using namespace marvin::data;
using marvin::data::test::TempDir;

namespace {

using marvin::data::test::kMinute;
constexpr const char* kZone = "Europe/Berlin";

std::int64_t local(const char* text) { return local_to_utc_ms(text, kZone); }

Reminder reminder(const char* title, const char* first_local,
                  Recurrence::Kind kind = Recurrence::Kind::kOnce) {
  Reminder r;
  r.title = title;
  r.time_zone = kZone;
  r.first_fire_utc_ms = local(first_local);
  r.recurrence.kind = kind;
  r.created_by = "test";
  return r;
}

struct Fixture {
  TempDir dir;
  ManualClock clock{local("2026-12-01T07:00")};
  SqliteStore store{[this] {
    StoreOptions o;
    o.path = dir.db();
    o.clock = &clock;
    return o;
  }()};
  boost::asio::io_context io;
  std::vector<Firing> fired;
  Scheduler scheduler{io, store, clock, [this](const Firing& f) { fired.push_back(f); }};

  // Moves the clock and lets the timer notice: re-arming with the new "now" makes the
  // due timer expire at once, so poll() runs it without any real waiting.
  void advance_to(std::int64_t utc_ms) {
    clock.set(utc_ms);
    scheduler.reminders_changed();
    io.restart();
    io.poll();
    io.restart();
    io.poll();
  }
};

}  // namespace

TEST_CASE("one timer, armed for the reminder due first among many") {
  Fixture f;
  std::int64_t earliest = INT64_MAX;
  for (int i = 0; i < 500; ++i) {
    Reminder r = reminder("r", "2026-12-02T08:00");
    r.first_fire_utc_ms += (i * 7919 % 500) * kMinute;  // scrambled order
    earliest = std::min(earliest, r.first_fire_utc_ms);
    f.store.add_reminder(r);
  }
  const auto report = f.scheduler.start();
  CHECK(report.fired.empty());
  CHECK(f.scheduler.armed_for() == earliest);
  CHECK(earliest == local("2026-12-02T08:00"));
}

TEST_CASE("a reminder fires through the timer when due, not before") {
  Fixture f;
  const auto id = f.store.add_reminder(reminder("take my pills", "2026-12-01T20:00"));
  f.scheduler.start();
  CHECK(f.scheduler.armed_for() == local("2026-12-01T20:00"));
  f.advance_to(local("2026-12-01T19:59"));
  CHECK(f.fired.empty());
  f.advance_to(local("2026-12-01T20:00"));
  REQUIRE(f.fired.size() == 1);
  CHECK(f.fired[0].reminder.id == id);
  CHECK(f.fired[0].due_utc_ms == local("2026-12-01T20:00"));
  CHECK_FALSE(f.fired[0].missed);
  CHECK(f.store.get_reminder(id)->state == Reminder::State::kDone);
  CHECK_FALSE(f.scheduler.armed_for().has_value());
  f.advance_to(local("2026-12-01T21:00"));
  CHECK(f.fired.size() == 1);
}

TEST_CASE("a daily reminder re-arms for the next day; snooze and done") {
  Fixture f;
  const auto id = f.store.add_reminder(
      reminder("water the plants", "2026-12-01T09:00", Recurrence::Kind::kDaily));
  f.scheduler.start();
  f.advance_to(local("2026-12-01T09:00"));
  REQUIRE(f.fired.size() == 1);
  CHECK(f.scheduler.armed_for() == local("2026-12-02T09:00"));

  // "Snooze ten minutes": fires at 09:10, then the series goes on tomorrow.
  CHECK(f.scheduler.snooze(id, 10));
  f.advance_to(local("2026-12-01T09:05"));
  CHECK(f.scheduler.armed_for() == local("2026-12-01T09:10"));
  f.advance_to(local("2026-12-01T09:10"));
  REQUIRE(f.fired.size() == 2);
  CHECK(f.fired[1].due_utc_ms == local("2026-12-01T09:10"));
  CHECK(f.scheduler.armed_for() == local("2026-12-02T09:00"));

  // "Done" on a one-off reminder before it fires: it never fires.
  const auto once = f.store.add_reminder(reminder("call Anna", "2026-12-01T12:00"));
  f.scheduler.reminders_changed();
  f.advance_to(local("2026-12-01T10:00"));
  CHECK(f.scheduler.armed_for() == local("2026-12-01T12:00"));
  CHECK(f.scheduler.done(once));
  f.advance_to(local("2026-12-01T12:30"));
  CHECK(f.fired.size() == 2);
  CHECK(f.scheduler.armed_for() == local("2026-12-02T09:00"));
  CHECK_FALSE(f.scheduler.snooze(424242, 5));
}

TEST_CASE("after downtime: recent misses fire with 'missed', older ones are only listed") {
  Fixture f;
  // Marvin was off from 07:00 to 12:00.
  const auto recent = f.store.add_reminder(reminder("take my pills", "2026-12-01T11:45"));
  const auto old = f.store.add_reminder(reminder("call the doctor", "2026-12-01T08:00"));
  const auto daily = f.store.add_reminder(
      reminder("water the plants", "2026-11-25T09:00", Recurrence::Kind::kDaily));
  Recurrence every_hour;
  every_hour.kind = Recurrence::Kind::kInterval;
  every_hour.interval_minutes = 60;
  every_hour.window_start_minute = 8 * 60;
  every_hour.window_end_minute = 22 * 60;
  Reminder drink = reminder("drink water", "2026-12-01T07:00");
  drink.recurrence = every_hour;
  const auto hourly = f.store.add_reminder(drink);
  const auto future = f.store.add_reminder(reminder("news", "2026-12-01T18:00"));

  f.clock.set(local("2026-12-01T12:10"));
  const StartupReport report = f.scheduler.start();

  // Spoken, in the order they fell due: the 12:00 slot of the hourly reminder (10 min
  // late; its earlier slots are not repeated) and the pills (25 min late).
  REQUIRE(f.fired.size() == 2);
  CHECK(f.fired[0].reminder.id == hourly);
  CHECK(f.fired[0].due_utc_ms == local("2026-12-01T12:00"));
  CHECK(f.fired[0].missed);
  CHECK(f.fired[1].reminder.id == recent);
  CHECK(f.fired[1].due_utc_ms == local("2026-12-01T11:45"));
  CHECK(f.fired[1].missed);
  CHECK(report.fired.size() == 2);
  // Listed, not spoken: the doctor call (4 h late) and a week of plant watering (once).
  REQUIRE(report.listed.size() == 2);
  CHECK(report.listed[0].reminder.id == daily);
  CHECK(report.listed[0].first_missed_utc_ms == local("2026-11-25T09:00"));
  CHECK(report.listed[0].last_missed_utc_ms == local("2026-12-01T09:00"));
  CHECK(report.listed[1].reminder.id == old);
  CHECK(f.store.recent_events(10).size() == 2);
  CHECK(f.store.recent_events(10)[0].kind == "reminder_missed");

  CHECK(f.store.get_reminder(old)->state == Reminder::State::kDone);
  CHECK(f.store.get_reminder(daily)->next_fire_utc_ms == local("2026-12-02T09:00"));
  CHECK(f.store.get_reminder(hourly)->next_fire_utc_ms == local("2026-12-01T13:00"));
  CHECK(f.store.get_reminder(future)->next_fire_utc_ms == local("2026-12-01T18:00"));
  CHECK(f.scheduler.armed_for() == local("2026-12-01T13:00"));
  // A second start finds nothing left to catch up.
  CHECK(f.scheduler.start().fired.empty());
  CHECK(f.fired.size() == 2);
}

TEST_CASE("a reminder cancelled while the timer waits does not fire") {
  Fixture f;
  const auto id = f.store.add_reminder(reminder("take my pills", "2026-12-01T20:00"));
  f.store.add_reminder(reminder("lock the door", "2026-12-01T22:00"));
  f.scheduler.start();
  CHECK(f.store.remove_reminder(id));
  f.scheduler.reminders_changed();
  f.advance_to(local("2026-12-01T20:30"));
  CHECK(f.fired.empty());
  CHECK(f.scheduler.armed_for() == local("2026-12-01T22:00"));
}

TEST_CASE("a daily reminder through the spring change fires at each valid local time") {
  Fixture f;
  f.clock.set(local("2026-03-28T00:00"));
  f.store.add_reminder(reminder("pills", "2026-03-28T02:30", Recurrence::Kind::kDaily));
  f.scheduler.start();
  f.advance_to(local("2026-03-28T02:30"));
  CHECK(f.scheduler.armed_for() == local("2026-03-29T03:00"));  // in the gap: 03:00
  f.advance_to(local("2026-03-29T03:00"));
  CHECK(f.scheduler.armed_for() == local("2026-03-30T02:30"));
  CHECK(f.fired.size() == 2);
}
