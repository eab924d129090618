// The home config file and its password file.
#include <doctest/doctest.h>
#include <sys/stat.h>

#include "home/config.h"
#include "support/files.h"

namespace marvin::home {
namespace {

using test_support::TempDir;
using test_support::write_text;

TEST_CASE("the config names broker, site and room; the password comes from its own file") {
  TempDir dir;
  write_text(dir / "pw", "s3cret\n");
  ::chmod((dir / "pw").c_str(), 0600);
  write_text(dir / "home.json", R"({"broker": {"host": "hub", "port": 8883, "tls": true,
      "user": "marvin", "password_file": "pw"}, "site": "flat", "room": "Kitchen",
      "commands": true, "answer_timeout_ms": 2000})");
  HomeConfig c = load_home_config(dir / "home.json");
  CHECK(c.broker.host == "hub");
  CHECK(c.broker.port == 8883);
  CHECK(c.broker.tls);
  CHECK(c.broker.user == "marvin");
  CHECK(c.broker.password == "s3cret");
  CHECK(c.site == "flat");
  CHECK(c.room == "Kitchen");
  CHECK(c.commands);
  CHECK(c.answer_timeout == std::chrono::milliseconds(2000));
}

TEST_CASE("a password file others can read is refused, naming the file and its mode") {
  TempDir dir;
  write_text(dir / "pw", "s3cret\n");
  ::chmod((dir / "pw").c_str(), 0644);
  write_text(dir / "home.json", R"({"broker": {"user": "marvin", "password_file": "pw"}})");
  CHECK_THROWS_WITH_AS(load_home_config(dir / "home.json"),
                       doctest::Contains(((dir / "pw").string() + " has mode 0644").c_str()), ConfigError);
  CHECK_THROWS_WITH_AS(read_password_file(dir / "pw"), doctest::Contains("chmod 600"), ConfigError);
  ::chmod((dir / "pw").c_str(), 0640);
  CHECK_THROWS_WITH_AS(read_password_file(dir / "pw"), doctest::Contains("has mode 0640"),
                       ConfigError);
  ::chmod((dir / "pw").c_str(), 0400);
  CHECK(read_password_file(dir / "pw") == "s3cret");
}

TEST_CASE("config errors name the file and the field") {
  TempDir dir;
  const std::string file = (dir / "home.json").string();
  write_text(dir / "home.json", R"({"broker": {"port": "1883"}})");
  CHECK_THROWS_WITH_AS(load_home_config(file),
                       (file + ": $.broker.port must be an integer, got \"1883\"").c_str(),
                       ConfigError);
  write_text(dir / "home.json", R"({"broker": {"password": "x"}})");
  CHECK_THROWS_WITH_AS(load_home_config(file), doctest::Contains("$.broker.password is not read"),
                       ConfigError);
  write_text(dir / "home.json", R"({"site": "a/b"})");
  CHECK_THROWS_WITH_AS(load_home_config(file), doctest::Contains("$.site must be"), ConfigError);
  write_text(dir / "home.json", "{");
  CHECK_THROWS_WITH_AS(load_home_config(file), doctest::Contains("not valid JSON at byte"),
                       ConfigError);
  CHECK_THROWS_WITH_AS(broker_from_address("hub:99999"), doctest::Contains("1..65535"), ConfigError);
  CHECK(broker_from_address("hub:1884").port == 1884);
}

}  // namespace
}  // namespace marvin::home
