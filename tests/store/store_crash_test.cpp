// Interrupted installs: a child process installs (or rolls back, or removes) and kills
// itself with SIGKILL at step N, for every step the operation has. After each kill the
// skill is either wholly the old version or wholly the new one, and recovery makes the
// lock file agree.
#include <doctest/doctest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <functional>

#include "store/installer.h"
#include "test_support.h"

using namespace marvin::store;
using namespace marvin::store::test;

namespace {

// Runs `op` in a child that SIGKILLs itself at its `kill_at`-th step. Returns true when
// the child was killed, false when the operation finished first.
bool run_killed_at(int kill_at, const fs::path& skills, const std::function<void(Installer&)>& op) {
  pid_t pid = ::fork();
  REQUIRE(pid >= 0);
  if (pid == 0) {
    int steps = 0;
    InstallOptions o;
    o.assume_yes = true;
    o.step_hook = [&](std::string_view) {
      if (steps++ == kill_at) ::raise(SIGKILL);
    };
    try {
      Installer inst(skills, o);
      op(inst);
    } catch (...) {
      ::_exit(2);
    }
    ::_exit(0);
  }
  int status = 0;
  REQUIRE(::waitpid(pid, &status, 0) == pid);
  if (WIFSIGNALED(status)) {
    REQUIRE(WTERMSIG(status) == SIGKILL);
    return true;
  }
  REQUIRE(WIFEXITED(status));
  REQUIRE(WEXITSTATUS(status) == 0);
  return false;
}

// The version whose files `current` shows, checked file by file against the packages;
// "" when the skill is not active.
std::string active_version(const fs::path& skills, const std::string& id,
                           const std::map<std::string, std::map<std::string, std::string>>& packages) {
  fs::path current = skills / id / "current";
  if (!fs::is_symlink(current)) return "";
  std::map<std::string, std::string> files;
  for (const auto& [path, content] : snapshot(current / "")) {
    if (content != "dir") files[path] = content.substr(5);
  }
  for (const auto& [version, want] : packages) {
    if (files == want) return version;
  }
  FAIL("current shows a mix of versions");
  return "?";
}

}  // namespace

TEST_CASE("an install killed at any step leaves the old or the new version, never a mix") {
  TempDir t;
  SecretKey key = generate_secret_key();
  fs::path skills = t / "skills";
  // Old and new differ in every file, and the new one has a file more.
  fs::path v1 = pack_signed(make_skill_dir(t / "src", "demo", "1.0.0", {"speech"}), t / "pkgs", key);
  fs::path v2 = pack_signed(make_skill_dir(t / "src", "demo", "2.0.0", {"speech"}, "^1.0", "extra.lua"), t / "pkgs", key);
  std::map<std::string, std::map<std::string, std::string>> packages{
      {"1.0.0", package_files(v1)}, {"2.0.0", package_files(v2)}};
  PackageSource s1{v1, {}, {key.public_key()}, std::nullopt, "test"};
  PackageSource s2{v2, {}, {key.public_key()}, std::nullopt, "test"};

  SUBCASE("first install: nothing or the new version") {
    int killed = 0;
    for (int step = 0; run_killed_at(step, skills, [&](Installer& i) { i.install(s1); }); ++step) {
      CAPTURE(step);
      std::string active = active_version(skills, "demo", packages);
      CHECK((active == "" || active == "1.0.0"));
      Installer(skills).recover();
      CHECK(active_version(skills, "demo", packages) == active);
      auto listed = Installer(skills).find("demo");
      CHECK((listed ? listed->version : std::string()) == active);
      CHECK(fs::is_empty(skills / ".store/staging"));
      if (fs::exists(skills / "demo")) Installer(skills).remove("demo");
      ++killed;
    }
    CHECK(killed > 5);  // the operation really has that many steps to cut
  }
  SUBCASE("upgrade: old or new, and recovery agrees") {
    int killed = 0;
    std::vector<std::string> seen;
    InstallOptions yes;
    yes.assume_yes = true;
    for (int step = 0;; ++step) {
      CAPTURE(step);
      if (fs::exists(skills / "demo")) Installer(skills).remove("demo");
      Installer(skills, yes).install(s1);
      if (!run_killed_at(step, skills, [&](Installer& i) { i.install(s2); })) break;
      ++killed;
      std::string active = active_version(skills, "demo", packages);
      CHECK((active == "1.0.0" || active == "2.0.0"));
      seen.push_back(active);
      Installer inst(skills);
      inst.recover();
      CHECK(active_version(skills, "demo", packages) == active);
      REQUIRE(inst.find("demo").has_value());
      CHECK(inst.find("demo")->version == active);
      // Whatever happened, the next attempt completes the upgrade.
      Installer(skills, yes).install(s2);
      CHECK(active_version(skills, "demo", packages) == "2.0.0");
      CHECK(Installer(skills).find("demo")->previous == "1.0.0");
    }
    CHECK(killed > 5);
    // Both outcomes happen: the kill points straddle the commit point.
    CHECK(std::find(seen.begin(), seen.end(), "1.0.0") != seen.end());
    CHECK(std::find(seen.begin(), seen.end(), "2.0.0") != seen.end());
  }
  SUBCASE("rollback and remove killed at any step") {
    InstallOptions yes;
    yes.assume_yes = true;
    for (int step = 0;; ++step) {
      CAPTURE(step);
      if (fs::exists(skills / "demo")) Installer(skills).remove("demo");
      Installer(skills, yes).install(s1);
      Installer(skills, yes).install(s2);
      if (!run_killed_at(step, skills, [&](Installer& i) { i.rollback("demo"); })) break;
      std::string active = active_version(skills, "demo", packages);
      CHECK((active == "1.0.0" || active == "2.0.0"));
      Installer(skills).recover();
      CHECK(Installer(skills).find("demo")->version == active);
    }
    for (int step = 0;; ++step) {
      CAPTURE(step);
      if (!fs::exists(skills / "demo")) Installer(skills, yes).install(s1);
      if (!run_killed_at(step, skills, [&](Installer& i) { i.remove("demo"); })) break;
      std::string active = active_version(skills, "demo", packages);
      CHECK((active == "" || active == "1.0.0"));
      Installer(skills).recover();
      auto listed = Installer(skills).find("demo");
      CHECK((listed ? listed->version : std::string()) == active);
      CHECK(fs::exists(skills / "demo") == !active.empty());
    }
  }
}
