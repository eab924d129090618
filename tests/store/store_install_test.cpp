// The installer: life cycle, permissions, downgrades, and every hostile or broken package,
// each refused with a message naming the entry or field while the installed skills and
// the lock file stay byte-for-byte the same.
#include <doctest/doctest.h>
#include <elf.h>

#include "store/installer.h"
#include "store/util.h"
#include "test_support.h"

using namespace marvin::store;
using namespace marvin::store::test;

namespace {

struct Fixture {
  TempDir tmp;
  SecretKey key = generate_secret_key();
  fs::path skills = tmp / "skills";
  fs::path pkgs = tmp / "pkgs";
  InstallOptions options;
  std::vector<SkillChange> changes;

  Fixture() {
    options.assume_yes = true;
    options.on_change = [this](const SkillChange& c) { changes.push_back(c); };
  }
  Installer installer() { return Installer(skills, options); }
  fs::path package(const std::string& id, const std::string& version, const std::vector<std::string>& perms = {},
                   const std::string& host_api = "^1.0") {
    return pack_signed(make_skill_dir(tmp / "src", id, version, perms, host_api), pkgs, key);
  }
  PackageSource source(const fs::path& p) { return PackageSource{p, {}, {key.public_key()}, std::nullopt, "test"}; }
  InstallResult install(const fs::path& p) { return installer().install(source(p)); }
  std::string current_version(const std::string& id) {
    return fs::read_symlink(skills / id / "current").filename().string();
  }
};

}  // namespace

TEST_CASE("life cycle: install, list, upgrade, rollback, remove") {
  Fixture f;
  fs::path v1 = f.package("demo", "1.0.0", {"speech"});
  fs::path v2 = f.package("demo", "1.1.0", {"speech"});

  InstallResult r = f.install(v1);
  CHECK(r.outcome == InstallResult::Outcome::kInstalled);
  CHECK(f.current_version("demo") == "1.0.0");
  CHECK(read_text(f.skills / "demo/current/main.lua") == "-- demo 1.0.0\nmarvin.say('hi')\n");
  std::vector<InstalledSkill> all = f.installer().list();
  REQUIRE(all.size() == 1);
  CHECK(all[0].version == "1.0.0");
  CHECK(all[0].digest == sha256_digest(read_file(v1)));
  CHECK(all[0].permissions == std::vector<std::string>{"speech"});
  CHECK_FALSE(all[0].previous.has_value());

  CHECK(f.install(v1).outcome == InstallResult::Outcome::kAlreadyInstalled);

  r = f.install(v2);
  CHECK(r.outcome == InstallResult::Outcome::kUpgraded);
  CHECK(r.replaced_version == "1.0.0");
  CHECK(f.current_version("demo") == "1.1.0");
  CHECK(f.installer().find("demo")->previous == "1.0.0");
  CHECK(read_text(f.skills / "demo/current/lib/util.lua") == "return {version = '1.1.0'}\n");

  InstalledSkill back = f.installer().rollback("demo");
  CHECK(back.version == "1.0.0");
  CHECK(back.previous == "1.1.0");
  CHECK(read_text(f.skills / "demo/current/main.lua") == "-- demo 1.0.0\nmarvin.say('hi')\n");
  CHECK(f.installer().rollback("demo").version == "1.1.0");  // a second rollback undoes the first

  // A third version drops the oldest from disk: only current and previous are kept.
  f.install(f.package("demo", "1.2.0", {"speech"}));
  CHECK(fs::exists(f.skills / "demo/versions/1.1.0"));
  CHECK_FALSE(fs::exists(f.skills / "demo/versions/1.0.0"));
  CHECK_FALSE(fs::exists(f.skills / "demo/receipts/1.0.0.json"));

  f.install(f.package("other", "0.1.0"));
  CHECK(f.installer().list().size() == 2);
  f.installer().remove("demo");
  CHECK_FALSE(fs::exists(f.skills / "demo"));
  REQUIRE(f.installer().list().size() == 1);
  CHECK(f.installer().list()[0].id == "other");
  CHECK_THROWS_WITH_AS(f.installer().remove("demo"), "skill \"demo\" is not installed", std::runtime_error);
  CHECK_THROWS_WITH_AS(f.installer().rollback("other"), "skill \"other\" has no previous version to roll back to",
                       std::runtime_error);

  // The host hook saw each change in order.
  REQUIRE(f.changes.size() == 7);
  CHECK(f.changes[0].kind == SkillChange::Kind::kInstalled);
  CHECK(f.changes[1].kind == SkillChange::Kind::kUpgraded);
  CHECK(f.changes[2].kind == SkillChange::Kind::kRolledBack);
  CHECK(f.changes[2].to_version == "1.0.0");
  CHECK(f.changes[6].kind == SkillChange::Kind::kRemoved);
}

TEST_CASE("permissions: approval on install, again when an upgrade adds some; refusal changes nothing") {
  Fixture f;
  f.options.assume_yes = false;
  std::vector<ApprovalRequest> asked;
  bool answer = true;
  f.options.approve = [&](const ApprovalRequest& r) {
    asked.push_back(r);
    return answer;
  };
  f.install(f.package("demo", "1.0.0", {"speech"}));
  REQUIRE(asked.size() == 1);
  CHECK(asked[0].added_permissions == std::vector<std::string>{"speech"});

  f.install(f.package("demo", "1.1.0", {"speech"}));  // nothing new: not asked
  CHECK(asked.size() == 1);

  answer = false;
  fs::path v3 = f.package("demo", "1.2.0", {"contacts", "speech"});
  auto before = snapshot(f.skills);
  CHECK_THROWS_WITH_AS(f.install(v3), "demo@1.2.0: permissions not approved (contacts); approve them or pass --yes",
                       std::runtime_error);
  CHECK(snapshot(f.skills) == before);
  REQUIRE(asked.size() == 2);
  CHECK(asked[1].installed_version == "1.1.0");
  CHECK(asked[1].permissions == std::vector<std::string>{"contacts", "speech"});

  f.options.approve = nullptr;  // no way to ask: refused too
  CHECK_THROWS_WITH_AS(f.install(v3), doctest::Contains("permissions not approved"), std::runtime_error);
  CHECK(snapshot(f.skills) == before);
}

TEST_CASE("downgrades need rollback or --allow-downgrade") {
  Fixture f;
  fs::path v1 = f.package("demo", "1.0.0");
  fs::path v2 = f.package("demo", "2.0.0");
  f.install(v2);
  auto before = snapshot(f.skills);
  CHECK_THROWS_WITH_AS(f.install(v1), doctest::Contains("demo@1.0.0 is older than the installed 2.0.0; use `marvin skill rollback demo` or --allow-downgrade"),
                       std::runtime_error);
  CHECK(snapshot(f.skills) == before);
  f.options.allow_downgrade = true;
  CHECK(f.install(v1).outcome == InstallResult::Outcome::kDowngraded);
  CHECK(f.current_version("demo") == "1.0.0");
}

TEST_CASE("validate hook and native architecture") {
  Fixture f;
  SUBCASE("the host's manifest validation refuses") {
    f.install(f.package("demo", "1.0.0"));
    auto before = snapshot(f.skills);
    f.options.validate = [](const fs::path& staged) {
      if (fs::exists(staged / "main.lua")) throw std::runtime_error("skill.json: intents: missing");
    };
    CHECK_THROWS_WITH_AS(f.install(f.package("demo", "1.1.0")),
                         doctest::Contains("demo-1.1.0.mskill: the host would not load it: skill.json: intents: missing"),
                         std::runtime_error);
    CHECK(snapshot(f.skills) == before);
  }
  SUBCASE("native library for this CPU installs; for another is refused") {
    auto native = [&](const std::string& version, std::uint16_t machine) {
      fs::path dir = f.tmp / ("native-" + version);
      write_text(dir / "skill.json", R"({"id":"dice","version":")" + version +
                                         R"(","kind":"native","host_api":"^1.0","library":"libdice.so"})");
      write_file_atomic(dir / "libdice.so", fake_elf_so(machine));
      return pack_signed(dir, f.pkgs, f.key);
    };
    f.install(native("1.0.0", host_elf_arch().machine));
    CHECK(f.current_version("dice") == "1.0.0");
    auto before = snapshot(f.skills);
    std::uint16_t foreign = host_elf_arch().machine == EM_AARCH64 ? EM_X86_64 : EM_AARCH64;
    CHECK_THROWS_WITH_AS(f.install(native("1.1.0", foreign)),
                         doctest::Contains(("libdice.so: built for " + ElfArch{foreign, ELFCLASS64, ELFDATA2LSB}.name() +
                                            ", this host is " + host_elf_arch().name()).c_str()),
                         std::runtime_error);
    CHECK(snapshot(f.skills) == before);
  }
}

TEST_CASE("hostile and broken packages are refused by name; installed skills and lock file unchanged") {
  Fixture f;
  f.install(f.package("demo", "1.0.0"));
  const std::string lock_before = read_text(f.skills / "skills.lock");
  const auto before = snapshot(f.skills);
  const std::string manifest = R"({"id":"demo","version":"1.1.0","kind":"lua","host_api":"^1.0"})";
  auto hostile = [&](const std::vector<RawEntry>& entries) {
    return write_signed(f.pkgs, "hostile.mskill", raw_archive(entries), f.key, "demo@1.1.0");
  };
  auto expect_refused = [&](const fs::path& pkg, const std::string& message) {
    CAPTURE(message);
    CHECK_THROWS_WITH_AS(f.install(pkg), doctest::Contains(message.c_str()), std::runtime_error);
    CHECK(read_text(f.skills / "skills.lock") == lock_before);
    CHECK(snapshot(f.skills) == before);
  };

  SUBCASE("path traversal") {
    expect_refused(hostile({{"skill.json", AE_IFREG, manifest, ""}, {"../evil.lua", AE_IFREG, "x", ""}}),
                   "entry '../evil.lua' escapes the package (path traversal");
    expect_refused(hostile({{"skill.json", AE_IFREG, manifest, ""}, {"lib/../../evil.lua", AE_IFREG, "x", ""}}),
                   "entry 'lib/../../evil.lua' escapes the package");
    CHECK_FALSE(fs::exists(f.tmp / "evil.lua"));
  }
  SUBCASE("absolute path") {
    expect_refused(hostile({{"skill.json", AE_IFREG, manifest, ""}, {"/tmp/evil.lua", AE_IFREG, "x", ""}}),
                   "entry '/tmp/evil.lua' has an absolute path");
  }
  SUBCASE("symbolic link") {
    expect_refused(hostile({{"skill.json", AE_IFREG, manifest, ""}, {"passwd", AE_IFLNK, "", "/etc/passwd"}}),
                   "entry 'passwd' is a symbolic link (to '/etc/passwd')");
  }
  SUBCASE("hard link") {
    expect_refused(hostile({{"skill.json", AE_IFREG, manifest, ""}, {"copy.json", AE_IFREG, "", "skill.json"}}),
                   "entry 'copy.json' is a hard link (to 'skill.json')");
  }
  SUBCASE("device file and FIFO") {
    expect_refused(hostile({{"skill.json", AE_IFREG, manifest, ""}, {"null", AE_IFCHR, "", ""}}),
                   "entry 'null' is a device file");
    expect_refused(hostile({{"skill.json", AE_IFREG, manifest, ""}, {"pipe", AE_IFIFO, "", ""}}),
                   "entry 'pipe' is a FIFO");
  }
  SUBCASE("duplicate entries") {
    expect_refused(hostile({{"skill.json", AE_IFREG, manifest, ""}, {"main.lua", AE_IFREG, "a", ""},
                            {"main.lua", AE_IFREG, "b", ""}}),
                   "entry 'main.lua' is a duplicate entry");
    expect_refused(hostile({{"skill.json", AE_IFREG, manifest, ""}, {"lib", AE_IFREG, "a", ""},
                            {"lib/x.lua", AE_IFREG, "b", ""}}),
                   "entry 'lib/x.lua' is inside 'lib', which is a file");
  }
  SUBCASE("too many files") {
    f.options.limits.max_entries = 8;
    std::vector<RawEntry> many{{"skill.json", AE_IFREG, manifest, ""}};
    for (int i = 0; i < 20; ++i) many.push_back({"f" + std::to_string(i) + ".lua", AE_IFREG, "x", ""});
    expect_refused(hostile(many), "too many entries: entry 'f7.lua' is number 9, the limit is 8");
  }
  SUBCASE("too many bytes after decompression (a zip bomb)") {
    f.options.limits.max_total_bytes = 1 << 20;
    fs::path bomb = hostile({{"skill.json", AE_IFREG, manifest, ""}, {"zeros.bin", AE_IFREG, std::string(8 << 20, '\0'), ""}});
    CHECK(fs::file_size(bomb) < 64 * 1024);  // small on disk, 8 MB inside
    expect_refused(bomb, "entry 'zeros.bin' makes the package larger than 1048576 bytes after decompression");
  }
  SUBCASE("truncated archive") {
    Bytes whole = raw_archive({{"skill.json", AE_IFREG, manifest, ""}, {"big.lua", AE_IFREG, std::string(200000, 'a') + std::string(200000, 'b'), ""}});
    Bytes cut(whole.begin(), whole.begin() + static_cast<long>(whole.size() / 2));
    expect_refused(write_signed(f.pkgs, "cut.mskill", cut, f.key, "demo@1.1.0"), "truncated");
  }
  SUBCASE("corrupted archive") {
    std::string text;
    for (int i = 0; i < 5000; ++i) text += std::to_string(i * 7919 % 10007) + " ";
    Bytes bytes = raw_archive({{"skill.json", AE_IFREG, manifest, ""}, {"data.lua", AE_IFREG, text, ""}});
    for (std::size_t i = bytes.size() / 2; i < bytes.size() / 2 + 64; ++i) bytes[i] ^= 0x5a;
    expect_refused(write_signed(f.pkgs, "bad.mskill", bytes, f.key, "demo@1.1.0"), "corrupted");
    expect_refused(write_signed(f.pkgs, "junk.mskill", Bytes(100, 7), f.key, "demo@1.1.0"), "corrupted archive");
  }
  SUBCASE("manifest id or version differs from what was signed") {
    expect_refused(hostile({{"skill.json", AE_IFREG, R"({"id":"evil","version":"1.1.0","kind":"lua","host_api":"^1.0"})", ""}}),
                   "skill.json: id: \"evil\" differs from the signed id \"demo\"");
    expect_refused(hostile({{"skill.json", AE_IFREG, R"({"id":"demo","version":"9.0.0","kind":"lua","host_api":"^1.0"})", ""}}),
                   "skill.json: version: \"9.0.0\" differs from the signed version \"1.1.0\"");
    expect_refused(hostile({{"main.lua", AE_IFREG, "x", ""}}), "skill.json missing from the package");
    expect_refused(hostile({{"skill.json", AE_IFREG, R"({"id":"demo","version":"1.1.0","kind":"lua"})", ""}}),
                   "skill.json: host_api: missing");
  }
  SUBCASE("signature missing, malformed, untrusted, by the wrong key, for another version") {
    fs::path v2 = f.package("demo", "1.1.0");
    std::string good_sig = read_text(signature_path_for(v2));
    fs::remove(signature_path_for(v2));
    expect_refused(v2, "demo-1.1.0.mskill.minisig: missing signature");
    write_text(signature_path_for(v2), "untrusted comment: x\nnot a signature\n");
    expect_refused(v2, "demo-1.1.0.mskill.minisig: malformed signature");
    SecretKey stranger = generate_secret_key();
    Bytes bytes = read_file(v2);
    write_text(signature_path_for(v2), sign_message(bytes, stranger, package_trusted_comment("demo@1.1.0", sha256_digest(bytes))));
    expect_refused(v2, "signed by untrusted key " + stranger.public_key().id_text());
    stranger.key_id = f.key.key_id;  // the wrong key, claiming the trusted key's id
    write_text(signature_path_for(v2), sign_message(bytes, stranger, package_trusted_comment("demo@1.1.0", sha256_digest(bytes))));
    expect_refused(v2, "signature verification failed for key " + f.key.public_key().id_text());
    // The genuine signature of 1.0.0 moved onto the 1.1.0 package.
    fs::path v1 = f.pkgs / "demo-1.0.0.mskill";
    write_text(signature_path_for(v2), read_text(signature_path_for(v1)));
    expect_refused(v2, "demo-1.1.0.mskill.minisig: signature verification failed");
    write_text(signature_path_for(v2), good_sig);
    CHECK(f.install(v2).outcome == InstallResult::Outcome::kUpgraded);  // and the real one works
  }
  SUBCASE("host API range we do not satisfy") {
    expect_refused(f.package("demo", "1.1.0", {}, ">=2.0"),
                   "skill.json: host_api: the skill needs host API \">=2.0\", this host provides " +
                       InstallOptions::default_host_api().text);
  }
  SUBCASE("package does not match the repository's index entry") {
    fs::path v2 = f.package("demo", "1.1.0");
    Bytes bytes = read_file(v2);
    IndexEntry e{"demo", parse_version("1.1.0", "v"), v2.filename().string(), sha256_digest(bytes), bytes.size(), "lua", {}, "^1.0"};
    PackageSource src = f.source(v2);
    src.expected = e;
    src.expected->size += 1;
    CHECK_THROWS_WITH_AS(f.installer().install(src), doctest::Contains("the index says"), std::runtime_error);
    src.expected = e;
    src.expected->digest = sha256_digest(Bytes{1});
    CHECK_THROWS_WITH_AS(f.installer().install(src), doctest::Contains("differs from the index's"), std::runtime_error);
    src.expected = e;
    src.expected->id = "other";
    CHECK_THROWS_WITH_AS(f.installer().install(src), doctest::Contains("signature is for demo@1.1.0, the index entry is other@1.1.0"),
                         std::runtime_error);
    src.expected = e;
    src.expected->permissions = {"motion"};
    CHECK_THROWS_WITH_AS(f.installer().install(src), doctest::Contains("permissions differ from the repository index"),
                         std::runtime_error);
    CHECK(snapshot(f.skills) == before);
  }
  CHECK(fs::is_empty(f.skills / ".store/staging"));
}

TEST_CASE("bytes after the gzip stream are refused like corruption") {
  Fixture f;
  fs::path v1 = f.package("demo", "1.0.0");
  Bytes padded = read_file(v1);
  padded.resize(padded.size() + 512, 0);
  CHECK_THROWS_WITH_AS(f.install(write_signed(f.pkgs, "padded.mskill", padded, f.key, "demo@1.0.0")),
                       doctest::Contains("corrupted archive (after entry 'skill.json')"), std::runtime_error);
  CHECK_FALSE(fs::exists(f.skills / "demo"));
}
