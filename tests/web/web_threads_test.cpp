// The web server with the host's threads around it (also run under ThreadSanitizer): console
// lines from several threads and events written by another thread reach every open page,
// each thread's lines in order; stopping the server with pages open ends them cleanly.
#include <doctest/doctest.h>

#include <map>
#include <thread>

#include "data/sqlite_store.h"
#include "support/files.h"
#include "web/auth.h"
#include "web/live.h"
#include "web/web_server.h"
#include "web_client.h"

namespace marvin::web {
namespace {

using nlohmann::json;

TEST_CASE("web threads: lines from four threads and events from a fifth reach three open pages") {
  test_support::TempDir tmp;
  data::StoreOptions so;
  so.path = tmp / "data/marvin.db";
  data::SqliteStore store(so);
  LiveFeed feed;
  set_password(password_file(tmp / "data/web"), "threads password", HashCost::kMinimum);
  WebOptions o;
  o.listen = "127.0.0.1:0";
  o.state_dir = tmp / "data/web";
  WebServer server(o, store, store, &feed);
  server.start();
  test::Browser b(server.port(), tmp / "data/web/cert.pem");
  REQUIRE(b.login("threads password").status == 200);
  std::vector<std::unique_ptr<test::Connection>> pages;
  for (int i = 0; i < 3; ++i) {
    pages.push_back(b.open_live());
    REQUIRE(pages.back()->next_event().first == "hello");
  }

  constexpr int kThreads = 4, kLines = 50, kEvents = 20;
  std::vector<std::thread> threads;
  for (int t = 0; t < kThreads; ++t) {
    threads.emplace_back([&feed, t] {
      for (int i = 0; i < kLines; ++i)
        feed.console_line("Marvin: thread " + std::to_string(t) + " line " + std::to_string(i));
    });
  }
  threads.emplace_back([&store] {
    for (int i = 0; i < kEvents; ++i)
      store.log_event("note", "threads", "event " + std::to_string(i));
  });
  for (auto& t : threads) t.join();

  for (auto& page : pages) {
    std::map<int, int> next_line;  // thread -> the line it must send next
    int turns = 0, events = 0;
    while (turns < kThreads * kLines || events < kEvents) {
      const auto [kind, data] = page->next_event();
      if (kind == "turn") {
        const std::string text = json::parse(data)["text"];
        int t = -1, i = -1;
        REQUIRE(std::sscanf(text.c_str(), "thread %d line %d", &t, &i) == 2);
        CHECK(i == next_line[t]);  // in order within a thread
        next_line[t] = i + 1;
        ++turns;
      } else if (kind == "event") {
        CHECK(json::parse(data)["message"] == "event " + std::to_string(events));
        ++events;
      }
    }
    CHECK(turns == kThreads * kLines);
    CHECK(events == kEvents);
  }
  CHECK(server.live_pages() == 3);
  CHECK(feed.snapshot()["turns"].size() == LiveFeed::kTurns);

  // Stopping with pages open closes them; a line said afterwards goes nowhere.
  server.stop();
  feed.console_line("Marvin: after the stop");
  CHECK_THROWS(pages[0]->next_event());
  CHECK(server.live_pages() == 0);
}

}  // namespace
}  // namespace marvin::web
