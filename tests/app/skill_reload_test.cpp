// The running host and the skill store, in one process: skills found in the store's layout
// (<dir>/<id>/current -> versions/<version>) and in plain folders, reloads that follow
// installs, upgrades, rollbacks and removals while other skills keep their instances, the
// automatic rollback of a version that fails to load, the host's validation refusing a
// package before activation, recover() at start, and the inotify watcher. Real files, real
// Lua skills, real signed packages and the real Installer.
#include <doctest/doctest.h>

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>
#include <vector>

#include "app/host.h"
#include "app/installed_skills.h"
#include "app/skill_watcher.h"
#include "store/installer.h"
#include "store/package_manifest.h"
#include "test_skills.h"

namespace marvin::app {
namespace {

using test::TempDir;
namespace fs = std::filesystem;

struct Store {
  TempDir tmp;
  fs::path dir = tmp / "skills";
  store::SecretKey key = store::generate_secret_key();

  store::Installer installer(bool validate = true) {
    store::InstallOptions o;
    o.assume_yes = true;
    o.durable = false;
    if (validate) o.validate = validate_skill_for_host;
    return store::Installer(dir, o);
  }
  store::InstallResult install(const fs::path& src, bool validate = true) {
    fs::path package = test::pack_signed(src, tmp / "packages", key);
    return installer(validate).install(
        {package, {}, {key.public_key()}, std::nullopt, "file:test"});
  }
  fs::path skill(const std::string& id, const std::string& version, const std::string& answer,
                 const std::string& main_lua = "") {
    return test::lua_skill(tmp / "src", id, version, answer, main_lua);
  }
};

// A host on in-memory data with only `dir`, whose console lines are kept.
struct TestHost {
  std::mutex mutex;
  std::condition_variable added;
  std::vector<std::string> lines;
  std::unique_ptr<Host> host;

  explicit TestHost(const fs::path& dir) {
    HostOptions o;
    o.builtin_skills = false;
    o.in_memory_data = true;
    o.time_zone = "UTC";
    o.skills_dirs = {dir};
    host = std::make_unique<Host>(std::move(o), [this](std::string_view line) {
      std::lock_guard lock(mutex);
      lines.emplace_back(line);
      added.notify_all();
    });
    host->load();
  }
  // What the host answers to `utterance` (the last console line it adds).
  std::string answer(const std::string& utterance) {
    std::size_t before;
    {
      std::lock_guard lock(mutex);
      before = lines.size();
    }
    host->manager().handle(utterance);
    std::lock_guard lock(mutex);
    std::string said;
    for (std::size_t i = before; i < lines.size(); ++i) {
      if (lines[i].starts_with("Marvin: ")) said = lines[i];
    }
    return said;
  }
  // The index of `line` once the host has shown it; fails after a generous timeout.
  std::size_t wait_line(const std::string& line) {
    std::unique_lock lock(mutex);
    std::size_t at = 0;
    bool found = added.wait_for(lock, std::chrono::seconds(60), [&] {
      auto it = std::find(lines.begin(), lines.end(), line);
      at = static_cast<std::size_t>(it - lines.begin());
      return it != lines.end();
    });
    REQUIRE_MESSAGE(found, "no line \"" << line << "\"");
    return at;
  }
  bool has_line(const std::string& line) {
    std::lock_guard lock(mutex);
    return std::find(lines.begin(), lines.end(), line) != lines.end();
  }
};

std::string lock_version(const fs::path& dir, const std::string& id) {
  auto lock = nlohmann::json::parse(test::read_text(dir / "skills.lock"));
  return lock["skills"][id]["version"].get<std::string>();
}

}  // namespace

TEST_CASE("find_skills: plain folders and installed skills, hidden and dangling ones skipped") {
  Store s;
  s.install(s.skill("hello", "1.0.0", "Hello one"));
  test::lua_skill(s.dir, "plain", "1.0.0", "Plain");
  fs::rename(s.dir / "plain-1.0.0-src", s.dir / "plain");
  test::lua_skill(s.dir, "hidden", "1.0.0", "Hidden");
  fs::rename(s.dir / "hidden-1.0.0-src", s.dir / ".hidden");
  fs::create_directories(s.dir / "dangling");
  fs::create_directory_symlink("versions/9.9.9", s.dir / "dangling" / "current");

  std::vector<skills::SkillSource> found = skills::find_skills(s.dir);
  REQUIRE(found.size() == 2);
  CHECK(found[0].origin == s.dir / "hello");
  CHECK(found[0].installed);
  CHECK(found[0].dir == fs::canonical(s.dir / "hello" / "versions" / "1.0.0"));
  CHECK(found[1].origin == s.dir / "plain");
  CHECK_FALSE(found[1].installed);
  CHECK(found[1].dir == s.dir / "plain");

  // A plain folder's stamp follows its files; an installed one's follows `current`.
  const std::string plain_stamp = found[1].stamp;
  fs::last_write_time(s.dir / "plain" / "main.lua",
                      fs::last_write_time(s.dir / "plain" / "main.lua") + std::chrono::hours(1));
  CHECK(skills::find_skills(s.dir)[1].stamp != plain_stamp);
  s.install(s.skill("hello", "1.1.0", "Hello two"));
  CHECK(skills::find_skills(s.dir)[0].dir == fs::canonical(s.dir / "hello" / "versions" / "1.1.0"));
  CHECK(skills::find_skills(s.tmp / "missing").empty());
}

TEST_CASE("the host follows installs, upgrades, rollbacks and removals; other skills stay") {
  Store s;
  test::lua_skill(s.dir, "other", "1.0.0", "Other here");
  fs::rename(s.dir / "other-1.0.0-src", s.dir / "other");
  TestHost t(s.dir);
  REQUIRE(t.host->registry().skills().size() == 1);
  const skills::LoadedSkill* other = t.host->registry().find("other");
  REQUIRE(other != nullptr);
  const skills::SkillInstance* other_instance = other->instance.get();
  CHECK(t.answer("hello greet").find("Sorry, I don't know") != std::string::npos);

  s.install(s.skill("hello", "1.0.0", "Hello one"));
  CHECK(t.host->reload_skills() == std::vector<std::string>{"skill hello 1.0.0 loaded"});
  CHECK(t.has_line("[skill hello 1.0.0 loaded]"));
  CHECK(t.host->registry().find("hello")->dir ==
        fs::canonical(s.dir / "hello" / "versions" / "1.0.0"));
  CHECK(t.answer("hello greet") == "Marvin: Hello one");

  s.install(s.skill("hello", "1.1.0", "Hello two"));
  CHECK(t.host->reload_skills() ==
        std::vector<std::string>{"skill hello 1.1.0 loaded (was 1.0.0)"});
  CHECK(t.answer("hello greet") == "Marvin: Hello two");
  // Nothing changed: nothing reloaded, and the other skill kept its instance throughout.
  CHECK(t.host->reload_skills().empty());
  CHECK(t.host->registry().find("other") == other);
  CHECK(t.host->registry().find("other")->instance.get() == other_instance);
  CHECK(t.answer("other greet") == "Marvin: Other here");

  s.installer().rollback("hello");
  CHECK(t.host->reload_skills() ==
        std::vector<std::string>{"skill hello 1.0.0 loaded (was 1.1.0)"});
  CHECK(t.answer("hello greet") == "Marvin: Hello one");

  const std::size_t intents = t.host->registry().interpreter().size();
  s.installer().remove("hello");
  CHECK(t.host->reload_skills() == std::vector<std::string>{"skill hello 1.0.0 unloaded"});
  CHECK(t.host->registry().find("hello") == nullptr);
  CHECK(t.host->registry().interpreter().size() == intents - 1);
  CHECK(t.answer("hello greet").find("Sorry, I don't know") != std::string::npos);
  CHECK(t.host->registry().find("other")->instance.get() == other_instance);

  // A plain folder removed goes too.
  fs::remove_all(s.dir / "other");
  CHECK(t.host->reload_skills() == std::vector<std::string>{"skill other 1.0.0 unloaded"});
  CHECK(t.host->registry().skills().empty());
}

TEST_CASE("a version that fails to load is rolled back and the previous one loaded") {
  Store s;
  s.install(s.skill("hello", "1.0.0", "Hello one"));
  TestHost t(s.dir);
  REQUIRE(t.answer("hello greet") == "Marvin: Hello one");

  // The host's validation passes (the manifest is fine); the code fails when it loads.
  s.install(s.skill("hello", "1.1.0", "", "error(\"broken on purpose\")\n"));
  REQUIRE(lock_version(s.dir, "hello") == "1.1.0");
  std::vector<std::string> report = t.host->reload_skills();
  REQUIRE(report.size() == 2);
  CHECK(report[0].starts_with("skill hello 1.1.0 failed to load ("));
  CHECK(report[0].find("broken on purpose") != std::string::npos);
  CHECK(report[0].ends_with("); rolled back to 1.0.0"));
  CHECK(report[1] == "skill hello 1.0.0 loaded");
  CHECK(t.has_line("[" + report[0] + "]"));
  CHECK(lock_version(s.dir, "hello") == "1.0.0");
  CHECK(s.installer().find("hello")->previous == std::optional<std::string>("1.1.0"));
  CHECK(t.answer("hello greet") == "Marvin: Hello one");
  // The rollback rewrote skills.lock; reloading again changes nothing.
  CHECK(t.host->reload_skills().empty());
}

TEST_CASE("a first version that fails to load has nothing to roll back to and is not retried") {
  Store s;
  TestHost t(s.dir);
  s.install(s.skill("hello", "1.0.0", "", "error(\"broken on purpose\")\n"));
  std::vector<std::string> report = t.host->reload_skills();
  REQUIRE(report.size() == 1);
  CHECK(report[0].starts_with("skill hello 1.0.0 failed to load ("));
  CHECK(report[0].ends_with("; no previous version to roll back to"));
  CHECK(t.host->registry().find("hello") == nullptr);
  CHECK(lock_version(s.dir, "hello") == "1.0.0");
  CHECK(t.host->reload_skills().empty());  // tried again only once it changes
  s.install(s.skill("hello", "1.0.1", "Fixed"));
  CHECK(t.host->reload_skills() == std::vector<std::string>{"skill hello 1.0.1 loaded"});
}

TEST_CASE("a reload requested while a long task runs waits until the task has finished") {
  Store s;
  s.install(s.skill("hello", "1.0.0", "Hello one"));
  fs::path waiter = s.tmp / "src" / "waiter";
  test::write_text(waiter / "skill.json", R"({"id": "waiter", "name": "Waiter", "version": "1.0.0",
    "kind": "lua", "host_api": {"min": "1.0"},
    "intents": [{"name": "wait", "templates": ["wait for me"], "execution": "long",
                 "time_limit_s": 600}]})");
  test::write_text(waiter / "main.lua", R"(marvin.on("wait", function()
  local answer = marvin.ask("Ready?")
  marvin.say("Done " .. tostring(answer))
end)
)");
  s.install(waiter);
  TestHost t(s.dir);
  std::thread loop([&] { t.host->loop().run(); });
  t.host->loop().post("wait for me");
  t.wait_line("Marvin: Ready?");
  // The task waits for its answer; the reload must wait for the task.
  s.install(s.skill("hello", "1.1.0", "Hello two"));
  t.host->request_reload();
  t.host->loop().post("go");
  const std::size_t reloaded = t.wait_line("[skill hello 1.1.0 loaded (was 1.0.0)]");
  const std::size_t done = t.wait_line("Marvin: Done go");
  CHECK(done < reloaded);
  t.host->loop().post("hello greet");
  t.wait_line("Marvin: Hello two");
  t.host->loop().close();
  loop.join();
}

TEST_CASE("install refuses a package the host would not load, naming the field; nothing changes") {
  Store s;
  s.install(s.skill("hello", "1.0.0", "Hello one"));
  const auto before = test::snapshot(s.dir);

  SUBCASE("host_api in the old range-string form (the store alone accepts it)") {
    fs::path src = test::lua_skill(s.tmp / "bad", "hello", "1.1.0", "x", "", "\"^1.0\"");
    // Without the host's validation the store's own checks pass...
    CHECK_NOTHROW(store::parse_package_manifest(test::read_text(src / "skill.json"), "skill.json"));
    try {
      s.install(src);
      FAIL("installed");
    } catch (const std::runtime_error& e) {
      std::string m = e.what();
      CHECK(m.find("the host would not load it: skill.json: $.host_api: ") != std::string::npos);
      CHECK(m.find(".store/staging") == std::string::npos);
    }
  }
  SUBCASE("a template naming an undeclared slot") {
    fs::path src = test::lua_skill(s.tmp / "bad", "hello", "1.1.0", "x");
    std::string json = test::read_text(src / "skill.json");
    json.replace(json.find("hello greet"), 11, "hello {who}");
    test::write_text(src / "skill.json", json);
    try {
      s.install(src);
      FAIL("installed");
    } catch (const std::runtime_error& e) {
      std::string m = e.what();
      CHECK(m.find("the host would not load it: skill.json: ") != std::string::npos);
      CHECK(m.find("who") != std::string::npos);
    }
  }
  CHECK(test::snapshot(s.dir) == before);
  CHECK(lock_version(s.dir, "hello") == "1.0.0");
}

TEST_CASE("host start finishes an interrupted store operation (recover)") {
  Store s;
  s.install(s.skill("hello", "1.0.0", "Hello one"));
  // What a killed installer leaves: a staging folder and a half-made pointer.
  test::write_text(s.dir / ".store" / "staging" / "hello-abc123" / "skill.json", "{}");
  fs::create_directory_symlink("versions/1.0.0", s.dir / "hello" / "current.tmp");
  TestHost t(s.dir);
  CHECK_FALSE(fs::exists(s.dir / ".store" / "staging" / "hello-abc123"));
  CHECK_FALSE(fs::exists(fs::symlink_status(s.dir / "hello" / "current.tmp")));
  CHECK(t.answer("hello greet") == "Marvin: Hello one");
}

TEST_CASE("a plain skills folder is not touched by recover()") {
  TempDir tmp;
  test::lua_skill(tmp.path(), "plain", "1.0.0", "Plain");
  const auto before = test::snapshot(tmp.path());
  TestHost t(tmp.path());
  CHECK(t.answer("plain greet") == "Marvin: Plain");
  CHECK(test::snapshot(tmp.path()) == before);  // no .store made, nothing deleted
}

namespace {

// Counts the watcher's calls; waits for more with a generous timeout.
struct Calls {
  std::mutex mutex;
  std::condition_variable changed;
  int count = 0;
  void add() {
    {
      std::lock_guard lock(mutex);
      ++count;
    }
    changed.notify_all();
  }
  int now() {
    std::lock_guard lock(mutex);
    return count;
  }
  bool wait_beyond(int seen) {
    std::unique_lock lock(mutex);
    return changed.wait_for(lock, std::chrono::seconds(30), [&] { return count > seen; });
  }
};

}  // namespace

TEST_CASE("the watcher sees the directory appear, the store's changes and reload requests") {
  Store s;
  Calls calls;
  SkillWatcher watcher({s.dir}, [&] { calls.add(); });  // s.dir does not exist yet

  // Made elsewhere with its .store and moved into place, so both are watched at once.
  fs::create_directories(s.tmp / "staging-dir" / ".store");
  int seen = calls.now();
  fs::rename(s.tmp / "staging-dir", s.dir);
  REQUIRE(calls.wait_beyond(seen));

  seen = calls.now();
  test::write_text(reload_request_file(s.dir), "reload\n");
  REQUIRE(calls.wait_beyond(seen));

  seen = calls.now();
  s.install(s.skill("hello", "1.0.0", "Hello one"));
  REQUIRE(calls.wait_beyond(seen));

  seen = calls.now();
  s.installer().remove("hello");
  REQUIRE(calls.wait_beyond(seen));
}

}  // namespace marvin::app
