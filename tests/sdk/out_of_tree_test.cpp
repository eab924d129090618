// The SDK as a skill developer gets it: `cmake --install` into a prefix, then the example
// dice skill configured and built as its own CMake project with find_package(MarvinSDK),
// its own unit test run there, and the resulting library loaded by the host's registry.
#include <doctest/doctest.h>
#include <unistd.h>

#include <cstdlib>
#include <deque>
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>

#include "skills/in_memory_personal_data.h"
#include "skills/manager.h"
#include "skills/registry.h"

namespace fs = std::filesystem;

namespace {

// Runs `command`, its output in `log`; returns the exit status.
int run(const std::string& command, const fs::path& log) {
  std::string full = command + " > '" + log.string() + "' 2>&1";
  int status = std::system(full.c_str());
  if (status != 0) {
    std::ifstream in(log);
    std::string output((std::istreambuf_iterator<char>(in)), {});
    MESSAGE("command failed: " << command << "\n" << output);
  }
  return status;
}

std::string q(const fs::path& p) { return "'" + p.string() + "'"; }

struct User : marvin::skills::User {
  std::vector<std::string> said;
  void say(std::string_view text) override { said.emplace_back(text); }
  std::optional<std::string> ask(std::string_view) override { return std::nullopt; }
};

}  // namespace

TEST_CASE("install the SDK, build the dice example out of tree, test it and load it") {
  fs::path work = fs::temp_directory_path() / ("marvin_sdk_oot_" + std::to_string(::getpid()));
  fs::remove_all(work);
  fs::create_directories(work);
  fs::path prefix = work / "prefix";
  fs::path build = work / "build";

  REQUIRE(run(std::string(CMAKE_COMMAND) + " --install " + q(MARVIN_BUILD_TREE) +
                  " --component marvin_sdk --prefix " + q(prefix),
              work / "install.log") == 0);
  CHECK(fs::exists(prefix / "include/marvin/skill.hpp"));
  CHECK(fs::exists(prefix / "include/marvin/testing/skill_harness.hpp"));
  CHECK(fs::exists(prefix / "lib/cmake/MarvinSDK/MarvinSDKConfig.cmake"));
  CHECK_FALSE(fs::exists(prefix / "include/skills"));  // no host internals in the SDK

  REQUIRE(run(std::string(CMAKE_COMMAND) + " -S " + q(DICE_SOURCE_DIR) + " -B " + q(build) +
                  " -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH=" + q(prefix) +
                  " -DCMAKE_CXX_COMPILER=" + q(CXX_COMPILER),
              work / "configure.log") == 0);
  REQUIRE(run(std::string(CMAKE_COMMAND) + " --build " + q(build) + " -j2", work / "build.log") ==
          0);
  REQUIRE(run(std::string(CTEST_COMMAND) + " --test-dir " + q(build) + " --output-on-failure",
              work / "ctest.log") == 0);
  fs::path skill = build / "skills" / "dice";
  REQUIRE(fs::exists(skill / "skill.so"));
  REQUIRE(fs::exists(skill / "skill.json"));

  // The host loads what the developer built and talks to it.
  marvin::skills::InMemoryPersonalData data;
  User user;
  marvin::skills::HostServices services;
  services.data = &data;
  services.now_ms = [] { return 1767603600000; };
  {
    marvin::skills::Registry registry(services);
    REQUIRE(registry.load_skill(skill));
    marvin::skills::Manager manager(registry, user);
    services.user = &manager;
    manager.handle("roll a die");
  }
  REQUIRE(user.said.size() == 1);
  CHECK(std::regex_match(user.said[0], std::regex("You rolled a [1-6]\\.")));
  fs::remove_all(work);
}
