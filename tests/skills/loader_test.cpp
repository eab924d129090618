// The native loader and the registry: ABI checks with both versions named, library life
// time, and broken skills skipped while the others load.
#include <dlfcn.h>
#include <doctest/doctest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "skills/in_memory_personal_data.h"
#include "skills/native_runtime.h"
#include "skills/registry.h"

namespace fs = std::filesystem;
using namespace marvin::skills;

namespace {

const fs::path kFixtures = FIXTURES_DIR;

std::string load_error(const std::string& fixture) {
  HostServices services;
  SkillContext context("echo", {}, services);
  Manifest manifest = load_manifest(kFixtures / fixture / "skill.json");
  NativeRuntime runtime;
  try {
    runtime.load(manifest, kFixtures / fixture, host_robot_api(), context.host());
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "(loaded)";
}

bool library_loaded(const fs::path& library) {
  void* handle = dlopen(library.c_str(), RTLD_NOW | RTLD_NOLOAD);
  if (handle) dlclose(handle);
  return handle != nullptr;
}

// A user that records what it is told.
struct Transcript : User {
  std::vector<std::string> said;
  void say(std::string_view text) override { said.emplace_back(text); }
  std::optional<std::string> ask(std::string_view) override { return std::nullopt; }
};

// A temporary skills directory, removed at the end.
struct TempDir {
  fs::path path = fs::temp_directory_path() / ("marvin_loader_test_" + std::to_string(::getpid()) +
                                               "_" + std::to_string(counter()++));
  TempDir() { fs::create_directories(path); }
  ~TempDir() { fs::remove_all(path); }
  static int& counter() {
    static int n = 0;
    return n;
  }
  void write(const fs::path& relative, const std::string& text) const {
    fs::create_directories((path / relative).parent_path());
    std::ofstream(path / relative) << text;
  }
};

}  // namespace

TEST_CASE("a skill with another ABI major is refused, naming both versions") {
  CHECK(load_error("major_newer") ==
        "skill 'echo' (" + (kFixtures / "major_newer" / "skill.so").string() +
            ") was built for Marvin ABI 2.0 but this host speaks ABI 1.5: the major versions "
            "must be equal; rebuild the skill with a matching SDK");
}

TEST_CASE("a skill built for a newer ABI minor is refused, naming both versions") {
  CHECK(load_error("minor_newer") ==
        "skill 'echo' (" + (kFixtures / "minor_newer" / "skill.so").string() +
            ") was built for Marvin ABI 1.7, newer than this host's ABI 1.5: update Marvin or "
            "rebuild the skill with an older SDK");
}

TEST_CASE("a skill built for ABI 1.3 (before guide_to) still loads on this 1.5 host") {
  CHECK(MARVIN_ABI_MINOR == 5);
  CHECK(load_error("api13") == "(loaded)");
}

TEST_CASE("a library claiming another skill id is refused") {
  // The fixture's skill.json says "not_echo"; its library says the same. Give the loader a
  // manifest with a different id to see the check.
  HostServices services;
  SkillContext context("echo", {}, services);
  Manifest manifest = load_manifest(kFixtures / "wrong_id" / "skill.json");
  manifest.id = "echo";
  NativeRuntime runtime;
  CHECK_THROWS_WITH(
      runtime.load(manifest, kFixtures / "wrong_id", host_robot_api(), context.host()),
      ("skill 'echo' (" + (kFixtures / "wrong_id" / "skill.so").string() +
       "): the library says it is skill 'not_echo' but skill.json says 'echo'")
          .c_str());
}

TEST_CASE("a missing library is named") {
  Manifest manifest = load_manifest(kFixtures / "good" / "skill.json");
  manifest.entry = "nothing.so";
  HostServices services;
  SkillContext context("echo", {}, services);
  NativeRuntime runtime;
  CHECK_THROWS_WITH(runtime.load(manifest, kFixtures / "good", host_robot_api(), context.host()),
                    ("skill 'echo': library " + (kFixtures / "good" / "nothing.so").string() +
                     " does not exist (\"entry\" in skill.json)")
                        .c_str());
}

TEST_CASE("the library stays loaded until its last instance is destroyed") {
  const fs::path library = kFixtures / "good" / "skill.so";
  REQUIRE_FALSE(library_loaded(library));
  Transcript user;
  HostServices services;
  services.user = &user;
  SkillContext a("echo", {}, services);
  SkillContext b("echo", {}, services);
  Manifest manifest = load_manifest(kFixtures / "good" / "skill.json");
  NativeRuntime runtime;
  auto first = runtime.load(manifest, kFixtures / "good", host_robot_api(), a.host());
  auto second = runtime.load(manifest, kFixtures / "good", host_robot_api(), b.host());
  CHECK(library_loaded(library));

  marvin_request request{sizeof(marvin_request), "hear", "{}", "echo listen"};
  std::string error;
  CHECK(second->handle(request, &error) == MARVIN_OK);
  CHECK(user.said == std::vector<std::string>{"echo heard: echo listen"});

  first.reset();
  CHECK(library_loaded(library));
  CHECK(second->handle(request, &error) == MARVIN_OK);  // still callable
  second.reset();
  CHECK_FALSE(library_loaded(library));
}

TEST_CASE("the registry skips a broken skill, loads the others, and reports why") {
  TempDir dir;
  // A good native skill: the fixture's library with a manifest in the temp dir.
  fs::create_directories(dir.path / "a_echo");
  fs::copy_file(kFixtures / "good" / "skill.so", dir.path / "a_echo" / "skill.so");
  fs::copy_file(kFixtures / "good" / "skill.json", dir.path / "a_echo" / "skill.json");
  // Broken: a wrong type in the manifest.
  dir.write("b_broken/skill.json", R"({"id": "broken", "name": "B", "version": 3, "kind": "native",
    "host_api": {"min": "1.0"}, "intents": [{"name": "x", "templates": ["x"]}]})");
  // Broken: ABI too new.
  fs::create_directories(dir.path / "c_new");
  fs::copy_file(kFixtures / "major_newer" / "skill.so", dir.path / "c_new" / "skill.so");
  dir.write("c_new/skill.json",
            R"({"id": "echo2", "name": "C", "version": "1.0.0", "kind": "native",
    "host_api": {"min": "1.0"}, "intents": [{"name": "x", "templates": ["newer"]}]})");
  // Broken: needs a newer Robot API than this host has.
  dir.write("d_future/skill.json",
            R"({"id": "future", "name": "D", "version": "1.0.0", "kind": "native",
    "host_api": {"min": "1.9"}, "intents": [{"name": "x", "templates": ["future"]}]})");
  // Broken: a kind without a runtime in this host.
  dir.write("e_lua/skill.json",
            R"({"id": "luaskill", "name": "E", "version": "1.0.0", "kind": "lua",
    "host_api": {"min": "1.0"}, "intents": [{"name": "x", "templates": ["lua thing"]}]})");

  InMemoryPersonalData data;
  HostServices services;
  services.data = &data;
  Registry registry(services);
  CHECK(registry.load_directory(dir.path) == 1);
  REQUIRE(registry.skills().size() == 1);
  CHECK(registry.skills()[0]->manifest.id == "echo");
  CHECK(registry.interpreter().size() == 1);
  REQUIRE(registry.errors().size() == 4);
  CHECK(registry.errors()[0].message == (dir.path / "b_broken" / "skill.json").string() +
                                            ": $.version: expected a string, got an integer");
  CHECK(registry.errors()[1].message.find(
            "was built for Marvin ABI 2.0 but this host speaks ABI 1." +
            std::to_string(MARVIN_ABI_MINOR)) != std::string::npos);
  CHECK(registry.errors()[2].message.find(
            "needs Robot API 1.9 to 1.99999 (\"host_api\") but this host has 1." +
            std::to_string(MARVIN_ROBOT_API_MINOR)) !=
        std::string::npos);
  CHECK(registry.errors()[3].message ==
        "skill 'luaskill': no runtime for kind \"lua\" in this host");

  // The refused skills left nothing behind: their sentences are not recognised.
  marvin::interpret::Context context;
  CHECK_FALSE(registry.interpreter().match("newer", context).has_value());
  CHECK_FALSE(registry.interpreter().match("future", context).has_value());
  CHECK(registry.interpreter().match("echo listen", context).has_value());

  // Loading the same skill again is refused: ids are unique.
  CHECK_FALSE(registry.load_skill(dir.path / "a_echo"));
  CHECK(registry.errors().back().message.find("a skill with this id is already loaded") !=
        std::string::npos);
  CHECK(registry.skills().size() == 1);
}

TEST_CASE("a missing skills directory is reported, not fatal") {
  HostServices services;
  Registry registry(services);
  CHECK(registry.load_directory("/nonexistent/marvin/skills") == 0);
  REQUIRE(registry.errors().size() == 1);
  CHECK(registry.errors()[0].message ==
        "skills directory /nonexistent/marvin/skills does not exist");
}
