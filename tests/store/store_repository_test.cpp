// Repositories: the signed example repository built from skills-examples/store-demo,
// install and upgrade from it, stale and replayed indexes, tampered indexes.
#include <doctest/doctest.h>

#include <cstdlib>

#include "store/installer.h"
#include "store/repository.h"
#include "store/util.h"
#include "test_support.h"

using namespace marvin::store;
using namespace marvin::store::test;

namespace {

fs::path demo_dir() {
  const char* src = std::getenv("MARVIN_SOURCE_DIR");
  if (src == nullptr) src = MARVIN_STORE_TEST_SOURCE_DIR;  // run outside CTest
  return fs::path(src) / "skills-examples" / "store-demo";
}

}  // namespace

TEST_CASE("the signed example repository: build from the example skills, search, install, upgrade") {
  TempDir t;
  SecretKey key = generate_secret_key();
  fs::path repo = t / "repo";
  pack_signed(demo_dir() / "hello", repo, key);
  pack_signed(demo_dir() / "notes", repo, key);
  RepositoryIndex built = build_repository_index(repo, "demo", key);
  CHECK(built.sequence == 1);
  REQUIRE(built.skills.size() == 2);
  CHECK(built.find("notes")->permissions == std::vector<std::string>{"storage"});
  CHECK(built.find("hello")->size == fs::file_size(repo / "hello-1.0.0.mskill"));

  fs::path skills = t / "skills";
  SeenIndexes seen(skills / ".store/seen-indexes.json");
  RepositoryConfig config{"demo", repo, {key.public_key()}};
  Repository r = open_repository(config, &seen);
  const IndexEntry* hello = r.index.find("hello");
  REQUIRE(hello != nullptr);
  InstallOptions o;
  o.assume_yes = true;
  Installer inst(skills, o);
  inst.install({r.package_path(*hello), {}, config.trusted_keys, *hello, "repo:demo"});
  CHECK(inst.find("hello")->source == "repo:demo");
  CHECK(read_text(skills / "hello/current/main.lua") == read_text(demo_dir() / "hello/main.lua"));

  // Publish hello 1.1.0: a new index with a higher sequence; upgrade from it.
  fs::path v2 = t / "hello-1.1.0";
  fs::copy(demo_dir() / "hello", v2);
  std::string manifest = read_text(v2 / "skill.json");
  manifest.replace(manifest.find("1.0.0"), 5, "1.1.0");
  write_text(v2 / "skill.json", manifest);
  pack_signed(v2, repo, key);
  CHECK(build_repository_index(repo, "demo", key).sequence == 2);
  r = open_repository(config, &seen);
  const IndexEntry* latest = r.index.find("hello");
  CHECK(latest->version.text == "1.1.0");
  CHECK(r.index.find("hello", "1.0.0") != nullptr);
  CHECK(inst.install({r.package_path(*latest), {}, config.trusted_keys, *latest, "repo:demo"}).outcome ==
        InstallResult::Outcome::kUpgraded);
}

TEST_CASE("a stale, replayed, tampered or untrusted index is refused") {
  TempDir t;
  SecretKey key = generate_secret_key();
  fs::path repo = t / "repo";
  pack_signed(demo_dir() / "hello", repo, key);
  build_repository_index(repo, "demo", key, 5);
  const std::string old_index = read_text(repo / "index.json");
  const std::string old_sig = read_text(repo / "index.json.minisig");
  build_repository_index(repo, "demo", key, 6);

  SeenIndexes seen(t / "seen.json");
  RepositoryConfig config{"demo", repo, {key.public_key()}};
  CHECK(open_repository(config, &seen).index.sequence == 6);
  CHECK(open_repository(config, &seen).index.sequence == 6);  // the same index again is fine
  const std::string seen_before = read_text(t / "seen.json");

  SUBCASE("stale: an older index, genuinely signed, served again") {
    write_text(repo / "index.json", old_index);
    write_text(repo / "index.json.minisig", old_sig);
    CHECK_THROWS_WITH_AS(open_repository(config, &seen),
                         doctest::Contains("sequence: stale index for repository \"demo\": sequence 5 is older than sequence 6"),
                         std::runtime_error);
  }
  SUBCASE("replayed: another index with the sequence already seen") {
    fs::remove(repo / "hello-1.0.0.mskill");
    fs::remove(repo / "hello-1.0.0.mskill.minisig");
    build_repository_index(repo, "demo", key, 6);
    CHECK_THROWS_WITH_AS(open_repository(config, &seen), doctest::Contains("replayed index"), std::runtime_error);
  }
  SUBCASE("tampered index") {
    std::string text = read_text(repo / "index.json");
    text.insert(text.find("\"permissions\": [") + 16, "\"motion\"");
    write_text(repo / "index.json", text);
    CHECK_THROWS_WITH_AS(open_repository(config, &seen), doctest::Contains("index.json.minisig: signature verification failed"),
                         std::runtime_error);
  }
  SUBCASE("untrusted key, missing signature") {
    RepositoryConfig other{"demo", repo, {generate_secret_key().public_key()}};
    CHECK_THROWS_WITH_AS(open_repository(other, &seen), doctest::Contains("signed by untrusted key"), std::runtime_error);
    fs::remove(repo / "index.json.minisig");
    CHECK_THROWS_WITH_AS(open_repository(config, &seen), doctest::Contains("index.json.minisig: missing"), std::runtime_error);
  }
  SUBCASE("the signed trusted comment must match the sequence inside") {
    std::string text = read_text(repo / "index.json");
    text.replace(text.find("\"sequence\": 6"), 13, "\"sequence\": 9");
    write_text(repo / "index.json", text);
    write_text(repo / "index.json.minisig",
               sign_message(Bytes(text.begin(), text.end()), key, "marvin-index demo sequence=6"));
    CHECK_THROWS_WITH_AS(open_repository(config, &seen), doctest::Contains("does not match the index"), std::runtime_error);
  }
  CHECK(read_text(t / "seen.json") == seen_before);
}

TEST_CASE("index fields are checked with their JSON path") {
  CHECK_THROWS_WITH_AS(parse_index(R"({"format":"marvin-index/1","name":"d","sequence":1,
      "skills":{"x":{"versions":{"1.0.0":{"file":"../x","digest":"","size":1,"kind":"lua","permissions":[],"host_api":"1"}}}}})", "index.json"),
      "index.json: $.skills.x.versions.1.0.0.file: must be a plain file name", std::runtime_error);
  CHECK_THROWS_WITH_AS(parse_index(R"({"format":"marvin-index/1","name":"d","sequence":-1,"skills":{}})", "index.json"),
                       doctest::Contains("$.sequence: wrong type"), std::runtime_error);
  CHECK_THROWS_WITH_AS(parse_index(R"({"format":"other","name":"d","sequence":1,"skills":{}})", "index.json"),
                       doctest::Contains("$.format: unsupported format"), std::runtime_error);
}
