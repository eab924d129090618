// Packing (reproducible bytes), manifests, versions and ranges, ELF architecture.
#include <doctest/doctest.h>
#include <elf.h>
#include <sys/stat.h>
#include <utime.h>

#include "store/archive.h"
#include "store/elf_arch.h"
#include "store/package.h"
#include "store/package_manifest.h"
#include "store/semver.h"
#include "test_support.h"

using namespace marvin::store;
using namespace marvin::store::test;

TEST_CASE("packing is reproducible: same files, same bytes, whatever the mtimes, modes and order") {
  TempDir a, b;
  fs::path one = make_skill_dir(a.path(), "demo", "1.0.0", {"speech"});
  // The same content written in the opposite order, with other times and modes.
  fs::path two = b.path() / "demo-src";
  write_text(two / "lib/util.lua", read_text(one / "lib/util.lua"));
  write_text(two / "main.lua", read_text(one / "main.lua"));
  write_text(two / "skill.json", read_text(one / "skill.json"));
  ::chmod((two / "main.lua").c_str(), 0600);
  struct utimbuf old_time {123456, 123456};
  ::utime((two / "skill.json").c_str(), &old_time);

  PackedSkill p1 = pack_skill(one);
  PackedSkill p2 = pack_skill(two);
  CHECK(p1.archive == p2.archive);
  CHECK(p1.digest == p2.digest);
  CHECK(p1.file_name() == "demo-1.0.0.mskill");
  // gzip header: no time stamp (bytes 4..7), so the packing time does not leak in.
  REQUIRE(p1.archive.size() > 10);
  CHECK(p1.archive[0] == 0x1f);
  CHECK(p1.archive[1] == 0x8b);
  CHECK((p1.archive[4] | p1.archive[5] | p1.archive[6] | p1.archive[7]) == 0);

  // A content change changes the bytes.
  write_text(two / "main.lua", "-- changed\n");
  CHECK(pack_skill(two).archive != p1.archive);
}

TEST_CASE("packed entries are sorted regular files with fixed owner, mode and mtime") {
  std::vector<ArchiveFile> files{{"z.lua", {'z'}}, {"a/b.lua", {'b'}}, {"skill.json", {'{', '}'}}};
  Bytes bytes = pack_files(files);
  std::map<std::string, Bytes> back = read_archive(bytes, ArchiveLimits{}, "t.mskill");
  REQUIRE(back.size() == 3);
  CHECK(back["a/b.lua"] == Bytes{'b'});
  std::reverse(files.begin(), files.end());
  CHECK(pack_files(files) == bytes);
  CHECK_THROWS_WITH_AS(pack_files({{"../x", {}}}), doctest::Contains("'../x'"), std::runtime_error);
  CHECK_THROWS_WITH_AS(pack_files({{"x", {}}, {"x", {}}}), doctest::Contains("appears twice"), std::runtime_error);
}

TEST_CASE("packing refuses a symlink in the skill folder and a folder without skill.json") {
  TempDir t;
  fs::path dir = make_skill_dir(t.path(), "demo", "1.0.0");
  fs::create_symlink("/etc/passwd", dir / "passwd");
  CHECK_THROWS_WITH_AS(pack_skill(dir), doctest::Contains("passwd: symbolic links cannot be packed"), std::runtime_error);
  fs::create_directories(t / "empty");
  CHECK_THROWS_WITH_AS(pack_skill(t / "empty"), doctest::Contains("skill.json: missing"), std::runtime_error);
}

TEST_CASE("package manifest: fields are checked and named") {
  auto parse = [](const std::string& j) { return parse_package_manifest(j, "skill.json"); };
  PackageManifest m = parse(R"({"id":"dice","version":"1.2.3-beta.1","kind":"native","host_api":">=1.0 <2.0",
                                "permissions":["speech","motion","speech"],"library":"libdice.so"})");
  CHECK(m.id == "dice");
  CHECK(m.version.prerelease == "beta.1");
  CHECK(m.permissions == std::vector<std::string>{"motion", "speech"});
  CHECK(m.library == "libdice.so");
  CHECK(parse(R"({"id":"d","version":"1.0.0","kind":"native","host_api":"1","native":{"library":"x.so"}})").library == "x.so");

  CHECK_THROWS_WITH_AS(parse(R"({"version":"1.0.0","kind":"lua","host_api":"1"})"),
                       "skill.json: id: missing (required)", std::runtime_error);
  CHECK_THROWS_WITH_AS(parse(R"({"id":"../x","version":"1.0.0","kind":"lua","host_api":"1"})"),
                       doctest::Contains("skill.json: id: \"../x\" is not a valid skill id"), std::runtime_error);
  CHECK_THROWS_WITH_AS(parse(R"({"id":"x","version":"1.0","kind":"lua","host_api":"1"})"),
                       doctest::Contains("version: \"1.0\" is not a semantic version"), std::runtime_error);
  CHECK_THROWS_WITH_AS(parse(R"({"id":"x","version":"1.0.0","kind":"python","host_api":"1"})"),
                       doctest::Contains("kind: \"python\""), std::runtime_error);
  CHECK_THROWS_WITH_AS(parse(R"({"id":"x","version":"1.0.0","kind":"lua","host_api":">=x"})"),
                       doctest::Contains("host_api"), std::runtime_error);
  CHECK_THROWS_WITH_AS(parse(R"({"id":"x","version":"1.0.0","kind":"lua","host_api":"1","permissions":[3]})"),
                       doctest::Contains("permissions[0]"), std::runtime_error);
  CHECK_THROWS_WITH_AS(parse(R"({"id":"x","version":"1.0.0","kind":"native","host_api":"1"})"),
                       doctest::Contains("library: missing"), std::runtime_error);
  CHECK_THROWS_WITH_AS(parse(R"({"id":"x","version":"1.0.0","kind":"native","host_api":"1","library":"../a.so"})"),
                       doctest::Contains("library: \"../a.so\" must be a plain file name"), std::runtime_error);
  CHECK_THROWS_WITH_AS(parse("{"), doctest::Contains("skill.json: not valid JSON"), std::runtime_error);
}

TEST_CASE("package manifest: the host's host_api object means the same range") {
  auto parse = [](const std::string& j) { return parse_package_manifest(j, "skill.json"); };
  auto v = [](const char* text) { return parse_version(text, "v", true); };
  PackageManifest any_minor = parse(R"({"id":"x","version":"1.0.0","kind":"lua","host_api":{"min":"1.1"}})");
  CHECK(any_minor.host_api.contains(v("1.1")));
  CHECK(any_minor.host_api.contains(v("1.9")));
  CHECK_FALSE(any_minor.host_api.contains(v("1.0")));
  CHECK_FALSE(any_minor.host_api.contains(v("2.0")));
  PackageManifest bounded =
      parse(R"({"id":"x","version":"1.0.0","kind":"lua","host_api":{"min":"1.0","max":"1.3"}})");
  CHECK(bounded.host_api.contains(v("1.3")));
  CHECK_FALSE(bounded.host_api.contains(v("1.4")));
  CHECK_THROWS_WITH_AS(parse(R"({"id":"x","version":"1.0.0","kind":"lua","host_api":{"max":"1.3"}})"),
                       "skill.json: host_api.min: expected a string such as \"1.0\"", std::runtime_error);
  CHECK_THROWS_WITH_AS(parse(R"({"id":"x","version":"1.0.0","kind":"lua","host_api":{"min":"1.0","max":2}})"),
                       "skill.json: host_api.max: expected a string such as \"1.3\"", std::runtime_error);
  CHECK_THROWS_WITH_AS(parse(R"({"id":"x","version":"1.0.0","kind":"lua","host_api":3})"),
                       doctest::Contains("skill.json: host_api: expected an object"), std::runtime_error);
}

TEST_CASE("semantic versions order as semver says, ranges hold or not") {
  auto v = [](const char* s) { return parse_version(s, "v", true); };
  CHECK(compare_versions(v("1.0.0-alpha"), v("1.0.0")) < 0);
  CHECK(compare_versions(v("1.0.0-alpha.2"), v("1.0.0-alpha.10")) < 0);
  CHECK(compare_versions(v("1.0.0-alpha.beta"), v("1.0.0-alpha.1")) > 0);
  CHECK(compare_versions(v("1.10.0"), v("1.9.0")) > 0);
  CHECK(compare_versions(v("1.0.0+build.5"), v("1.0.0")) == 0);
  CHECK_THROWS(parse_version("01.0.0", "v"));
  CHECK_THROWS(parse_version("1.0.0-", "v"));

  CHECK(VersionRange::parse(">=1.0 <2.0", "r").contains(v("1.5")));
  CHECK_FALSE(VersionRange::parse(">=1.0 <2.0", "r").contains(v("2.0")));
  CHECK(VersionRange::parse("^1.2", "r").contains(v("1.9")));
  CHECK_FALSE(VersionRange::parse("^1.2", "r").contains(v("1.1")));
  CHECK_FALSE(VersionRange::parse("~1.2", "r").contains(v("1.3")));
  CHECK(VersionRange::parse(">=1.0, <=1.0", "r").contains(v("1.0")));
  CHECK_FALSE(VersionRange::parse(">1.0", "r").contains(v("1.0")));
  CHECK(VersionRange::parse("=1.0", "r").contains(v("1.0.0")));
  CHECK_THROWS_WITH_AS(VersionRange::parse("", "host_api"), "host_api: empty version range", std::runtime_error);
}

TEST_CASE("ELF architecture of a shared object is read from its header") {
  CHECK(read_elf_arch(fake_elf_so(EM_AARCH64), "x.so").machine == EM_AARCH64);
  CHECK(read_elf_arch(fake_elf_so(EM_AARCH64), "x.so").name() == "aarch64 (64-bit, little-endian)");
  CHECK(read_elf_arch(fake_elf_so(host_elf_arch().machine), "x.so") == host_elf_arch());
  CHECK_THROWS_WITH_AS(read_elf_arch(Bytes(64, 0), "x.so"), "x.so: not an ELF file (bad magic)", std::runtime_error);
  Bytes exec = fake_elf_so(EM_X86_64);
  exec[16] = ET_EXEC;
  CHECK_THROWS_WITH_AS(read_elf_arch(exec, "x.so"), doctest::Contains("not a shared object"), std::runtime_error);
}
