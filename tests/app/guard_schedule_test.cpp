// Guard mode by schedule (issue 22; core/app/guard_schedule.h): what a schedule says, the
// reminder scheduler turning guard mode on and off at its times (a manual clock, no waiting),
// the same after a restart (the reminders are in the SQLite file), and bad input refused with
// a message that names the word, storing nothing (the `marvin guard schedule` CLI too).
#include "app/guard_schedule.h"

#include <doctest/doctest.h>

#include <boost/asio/io_context.hpp>
#include <memory>
#include <string>

#include "data/recurrence.h"
#include "data/scheduler.h"
#include "data/sqlite_store.h"
#include "skills/guard.h"
#include "skills/scripted_eyes.h"
#include "support/child_process.h"
#include "support/files.h"

using marvin::app::GuardPlan;
using marvin::app::parse_guard_plan;

namespace {

std::int64_t guard_utc_ms(const char* local) { return marvin::data::local_to_utc_ms(local, "UTC"); }

// The store, the scheduler on a manual clock and a guard that only keeps its state; the
// scheduler's firings go through apply_guard_firing as in the host.
struct GuardClock {
  explicit GuardClock(const std::filesystem::path& db, std::int64_t now) : clock(now) {
    marvin::data::StoreOptions o;
    o.path = db;
    o.clock = &clock;
    store = std::make_unique<marvin::data::SqliteStore>(o);
    marvin::skills::GuardOptions g;
    g.watch = false;
    guard = std::make_unique<marvin::skills::Guard>(
        eyes, nullptr, [this] { return clock.now_utc_ms(); },
        [](const std::string&, const std::string&) {}, g);
    scheduler = std::make_unique<marvin::data::Scheduler>(
        io, *store, clock, [this](const marvin::data::Firing& f) {
          if (auto s = marvin::app::apply_guard_firing(f.reminder, guard.get())) said.push_back(*s);
        });
    scheduler->start();
  }
  void advance_to(std::int64_t ms) {
    clock.set(ms);
    scheduler->reminders_changed();
    for (int i = 0; i < 2; ++i) {
      io.restart();
      io.poll();
    }
  }
  marvin::data::ManualClock clock;
  std::unique_ptr<marvin::data::SqliteStore> store;
  marvin::skills::ScriptedEyes eyes{[](std::string) {}};
  std::unique_ptr<marvin::skills::Guard> guard;
  boost::asio::io_context io;
  std::unique_ptr<marvin::data::Scheduler> scheduler;
  std::vector<std::string> said;
};

}  // namespace

TEST_CASE("guard schedule: what the user says becomes days and times") {
  GuardPlan p = parse_guard_plan("every night at 10 pm");
  CHECK(p.days == 0x7f);
  CHECK(p.on_minute == 22 * 60);
  CHECK_FALSE(p.off_minute.has_value());
  p = parse_guard_plan("on weekdays from 9 to 5");
  CHECK(p.days == 0x1f);
  CHECK(p.on_minute == 9 * 60);
  CHECK(p.off_minute == 17 * 60);
  p = parse_guard_plan("On Mondays and Fridays from 10:30 pm to 7 am");
  CHECK(p.days == 0x11);
  CHECK(p.on_minute == 22 * 60 + 30);
  CHECK(p.off_minute == 7 * 60);
  CHECK(p.when == "on mondays and fridays from 10:30 pm to 7 am");
  CHECK(parse_guard_plan("weekends at noon").days == 0x60);
  CHECK(parse_guard_plan("daily at 21:15").on_minute == 21 * 60 + 15);
}

TEST_CASE("guard schedule: bad input names the word and what was expected") {
  CHECK_THROWS_WITH(parse_guard_plan("on fundays at 10 pm"),
                    "unknown day 'fundays' (expected monday to sunday, weekdays, weekends, every "
                    "day or every night)");
  CHECK_THROWS_WITH(parse_guard_plan("every night at 25 pm"),
                    "'25 pm' is not a time (with am or pm the hour is 1 to 12)");
  CHECK_THROWS_WITH(parse_guard_plan("every day at 24:00"),
                    "'24:00' is not a time (hours are 0 to 23)");
  CHECK_THROWS_WITH(parse_guard_plan("every night"),
                    "when? expected 'at 10 pm' or 'from 9 to 5' in 'every night'");
  CHECK_THROWS_WITH(parse_guard_plan("on weekdays from 9"),
                    "'from 09:00' needs an end: expected 'to' and a time");
  CHECK_THROWS_WITH(parse_guard_plan("every day from 9 am to 9 am"),
                    "the window from 09:00 to 09:00 is empty");
  CHECK_THROWS_WITH(parse_guard_plan("every day at 9 am please"),
                    "unexpected 'please' after the time");
}

// Monday 30 November 2026, UTC.
TEST_CASE(
    "guard schedule: on weekdays from 9 to 5 turns guard mode on and off; after a restart too") {
  marvin::test_support::TempDir dir;
  const auto db = dir.path() / "marvin.db";
  {
    GuardClock g(db, guard_utc_ms("2026-11-30T08:00"));
    for (const auto& r : marvin::app::guard_plan_reminders(
             parse_guard_plan("on weekdays from 9 to 5"), "UTC", g.clock.now_utc_ms())) {
      g.store->add_reminder(r);
    }
    g.advance_to(guard_utc_ms("2026-11-30T08:59"));
    CHECK_FALSE(g.guard->state().on);
    g.advance_to(guard_utc_ms("2026-11-30T09:00"));
    CHECK(g.guard->state().on);
    g.advance_to(guard_utc_ms("2026-11-30T16:59"));
    CHECK(g.guard->state().on);
    g.advance_to(guard_utc_ms("2026-11-30T17:00"));
    CHECK_FALSE(g.guard->state().on);
    CHECK(g.guard->state().by == marvin::app::kOffBySchedule);
    REQUIRE(g.said.size() == 2);
    CHECK(g.said[0] == "Guard mode is on, as scheduled (on weekdays from 9 to 5).");
    CHECK(g.said[1] == "Guard mode is off, as scheduled (on weekdays from 9 to 5).");
  }
  // A restart: a new store, scheduler and guard on the same file, the next morning.
  GuardClock g(db, guard_utc_ms("2026-12-01T08:30"));
  CHECK_FALSE(g.guard->state().on);
  g.advance_to(guard_utc_ms("2026-12-01T09:00"));
  CHECK(g.guard->state().on);
  // Saturday: nothing comes on.
  g.advance_to(guard_utc_ms("2026-12-01T17:00"));
  g.advance_to(guard_utc_ms("2026-12-05T09:00"));
  CHECK_FALSE(g.guard->state().on);
}

TEST_CASE("guard schedule: a window past midnight ends on the next day") {
  const auto rs = marvin::app::guard_plan_reminders(
      parse_guard_plan("on fridays from 10 pm to 7 am"), "UTC", guard_utc_ms("2026-11-30T08:00"));
  REQUIRE(rs.size() == 2);
  CHECK(rs[0].next_fire_utc_ms == guard_utc_ms("2026-12-04T22:00"));  // Friday
  CHECK(rs[1].next_fire_utc_ms == guard_utc_ms("2026-12-05T07:00"));  // Saturday
  CHECK(marvin::app::guard_switch(rs[0]) == std::optional<bool>(true));
  CHECK(marvin::app::guard_switch(rs[1]) == std::optional<bool>(false));
}

#ifdef MARVIN_EXE
TEST_CASE("marvin guard schedule add|list|cancel; bad input changes nothing") {
  using marvin::test_support::ChildProcess;
  using marvin::test_support::exit_code;
  marvin::test_support::TempDir dir;
  const std::string data = dir.path().string();
  auto cli = [&](std::vector<std::string> args, int expected_exit = 0) {
    args.insert(args.begin(), {MARVIN_EXE, "guard", "schedule"});
    args.insert(args.end(), {"--data-dir", data});
    ChildProcess c(args);
    CHECK(exit_code(c.finish()) == expected_exit);
    return c.output() + c.errors();
  };
  const std::string added = cli({"add", "every night at 10 pm", "--tz", "UTC"});
  CHECK(added.find("on   next ") != std::string::npos);
  CHECK(added.find(" 22:00 (every night at 10 pm)") != std::string::npos);
  const std::string before = cli({"list"});
  CHECK(before.find("(every night at 10 pm)") != std::string::npos);
  CHECK(cli({"add", "every night at 25 pm"}, 2)
            .find("guard schedule: '25 pm' is not a time (with am or pm the hour is 1 to 12)") !=
        std::string::npos);
  CHECK(cli({"add", "on fundays at 9 am"}, 2).find("guard schedule: unknown day 'fundays'") !=
        std::string::npos);
  CHECK(cli({"list"}) == before);
  CHECK(cli({"cancel", "99"}, 1).find("guard schedule: no guard schedule with id 99") !=
        std::string::npos);
  CHECK(cli({"cancel", before.substr(0, before.find(' '))}) ==
        "cancelled the guard schedule 'every night at 10 pm'\n");
  CHECK(cli({"list"}) == "no guard schedule\n");
}
#endif
