// minisign signatures: our own round trip, every way a signature can be wrong, and
// interoperability with Debian's real `minisign` in both directions.
#include <doctest/doctest.h>

#include "store/minisign.h"
#include "store/package.h"
#include "store/util.h"
#include "test_support.h"

using namespace marvin::store;
using namespace marvin::store::test;

namespace {

Bytes bytes_of(const std::string& s) { return Bytes(s.begin(), s.end()); }

std::string replace_line(const std::string& text, int line, const std::string& with) {
  std::vector<std::string> lines;
  std::string cur;
  for (char c : text) {
    if (c == '\n') {
      lines.push_back(cur);
      cur.clear();
    } else {
      cur += c;
    }
  }
  lines[static_cast<std::size_t>(line)] = with;
  std::string out;
  for (const std::string& l : lines) out += l + "\n";
  return out;
}

}  // namespace

TEST_CASE("sign and verify round trip; keys survive their file formats") {
  SecretKey sk = generate_secret_key();
  SecretKey sk2 = parse_secret_key(format_secret_key(sk), "k.key");
  CHECK(sk2.key == sk.key);
  CHECK(sk2.key_id == sk.key_id);
  PublicKey pk = parse_public_key(format_public_key(sk.public_key()), "k.pub");
  CHECK(pk.key == sk.public_key().key);
  CHECK(parse_public_key(pk.base64(), "-P").key_id == pk.key_id);

  Bytes msg = bytes_of("hello");
  std::string sig = sign_message(msg, sk, "marvin-skill a@1.0.0 x");
  CHECK(verify_message(msg, parse_signature(sig, "s"), {pk}, "s") == "marvin-skill a@1.0.0 x");
}

TEST_CASE("a wrong signature is refused with the reason") {
  SecretKey sk = generate_secret_key();
  SecretKey other = generate_secret_key();
  PublicKey pk = sk.public_key();
  Bytes msg = bytes_of("package bytes");
  std::string sig = sign_message(msg, sk, "trusted");

  SUBCASE("content changed") {
    CHECK_THROWS_WITH_AS(verify_message(bytes_of("package bytez"), parse_signature(sig, "p.minisig"), {pk}, "p.minisig"),
                         doctest::Contains("p.minisig: signature verification failed"), std::runtime_error);
  }
  SUBCASE("untrusted key: its id is not among the trusted ones") {
    CHECK_THROWS_WITH_AS(verify_message(msg, parse_signature(sig, "p.minisig"), {other.public_key()}, "p.minisig"),
                         doctest::Contains(("signed by untrusted key " + pk.id_text()).c_str()), std::runtime_error);
  }
  SUBCASE("valid signature by the wrong key that claims the trusted key's id") {
    SecretKey forger = generate_secret_key();
    forger.key_id = sk.key_id;
    std::string forged = sign_message(msg, forger, "trusted");
    CHECK_THROWS_WITH_AS(verify_message(msg, parse_signature(forged, "p.minisig"), {pk}, "p.minisig"),
                         doctest::Contains(("signature verification failed for key " + pk.id_text()).c_str()), std::runtime_error);
  }
  SUBCASE("trusted comment tampered") {
    std::string tampered = replace_line(sig, 2, "trusted comment: something else");
    CHECK_THROWS_WITH_AS(verify_message(msg, parse_signature(tampered, "p.minisig"), {pk}, "p.minisig"),
                         doctest::Contains("trusted comment tampered"), std::runtime_error);
  }
  SUBCASE("malformed signature files") {
    CHECK_THROWS_WITH_AS(parse_signature("garbage", "p.minisig"), doctest::Contains("p.minisig: malformed signature: expected 4 lines"),
                         std::runtime_error);
    CHECK_THROWS_WITH_AS(parse_signature(replace_line(sig, 1, "!!!notbase64"), "p.minisig"),
                         doctest::Contains("signature is not valid base64"), std::runtime_error);
    CHECK_THROWS_WITH_AS(parse_signature(replace_line(sig, 1, "RWQAAA=="), "p.minisig"),
                         doctest::Contains("expected 74"), std::runtime_error);
    CHECK_THROWS_WITH_AS(parse_signature(replace_line(sig, 2, "no prefix"), "p.minisig"),
                         doctest::Contains("line 3 is not a trusted comment"), std::runtime_error);
  }
  SUBCASE("secret key checksum") {
    std::string key = format_secret_key(sk);
    std::string broken = key;
    broken[broken.size() - 10] = broken[broken.size() - 10] == 'A' ? 'B' : 'A';
    CHECK_THROWS_WITH_AS(parse_secret_key(broken, "k.key"), doctest::Contains("k.key: secret key checksum mismatch"),
                         std::runtime_error);
  }
}

TEST_CASE("package signatures bind id@version and the digest") {
  SecretKey sk = generate_secret_key();
  Bytes pkg = bytes_of("pretend archive");
  std::string sig = sign_message(pkg, sk, package_trusted_comment("dice@1.0.0", sha256_digest(pkg)));
  PackageClaim c = verify_package_signature(pkg, sig, {sk.public_key()}, "dice.mskill");
  CHECK(c.id_at_version() == "dice@1.0.0");
  // The same signature on other bytes (another version) fails.
  CHECK_THROWS_WITH_AS(verify_package_signature(bytes_of("other archive"), sig, {sk.public_key()}, "dice-1.1.0.mskill"),
                       doctest::Contains("dice-1.1.0.mskill.minisig: signature verification failed"), std::runtime_error);
  // A genuine signature whose trusted comment names other bytes.
  std::string lying = sign_message(pkg, sk, package_trusted_comment("dice@1.0.0", sha256_digest(bytes_of("x"))));
  CHECK_THROWS_WITH_AS(verify_package_signature(pkg, lying, {sk.public_key()}, "dice.mskill"),
                       doctest::Contains("trusted comment is for package digest"), std::runtime_error);
  std::string plain = sign_message(pkg, sk, "just a file");
  CHECK_THROWS_WITH_AS(verify_package_signature(pkg, plain, {sk.public_key()}, "dice.mskill"),
                       doctest::Contains("trusted comment \"just a file\" is not \"marvin-skill"), std::runtime_error);
}

TEST_CASE("interop: keys made by minisign -G -W; minisign verifies ours, we verify minisign's") {
  TempDir t;
  REQUIRE_MESSAGE(run("minisign -v > /dev/null 2>&1") == 0, "the minisign tool is needed (deps/debian-packages.txt)");
  fs::path pub = t / "k.pub", key = t / "k.key";
  REQUIRE(run("minisign -G -W -p " + pub.string() + " -s " + key.string() + " > /dev/null 2>&1 < /dev/null") == 0);
  SecretKey sk = load_secret_key(key);
  PublicKey pk = load_public_key(pub);
  CHECK(sk.public_key().key == pk.key);
  CHECK(sk.key_id == pk.key_id);

  fs::path skill = make_skill_dir(t.path(), "demo", "1.0.0");
  fs::path pkg = pack_signed(skill, t / "out", sk);

  SUBCASE("minisign verifies our signature and shows our trusted comment") {
    fs::path out = t / "verify.txt";
    CHECK(run("minisign -V -p " + pub.string() + " -m " + pkg.string() + " > " + out.string() + " 2>&1") == 0);
    CHECK(read_text(out).find("marvin-skill demo@1.0.0 sha256:") != std::string::npos);
    // And refuses it on changed bytes: the check above could fail.
    write_text(t / "changed.mskill", read_text(pkg) + "x");
    fs::copy_file(signature_path_for(pkg), t / "changed.mskill.minisig");
    CHECK(run("minisign -V -q -p " + pub.string() + " -m " + (t / "changed.mskill").string() + " > /dev/null 2>&1") != 0);
  }
  SUBCASE("we verify minisign's prehashed (default) and legacy signatures") {
    Bytes bytes = read_file(pkg);
    std::string comment = package_trusted_comment("demo@1.0.0", sha256_digest(bytes));
    for (std::string flags : {"", "-l"}) {
      CAPTURE(flags);
      fs::remove(signature_path_for(pkg));
      REQUIRE(run("minisign -S " + flags + " -s " + key.string() + " -m " + pkg.string() + " -t '" + comment +
                  "' > /dev/null 2>&1 < /dev/null") == 0);
      Signature sig = parse_signature(read_text(signature_path_for(pkg)), "minisig");
      CHECK(sig.prehashed == flags.empty());
      PackageClaim c = verify_package_signature(bytes, read_text(signature_path_for(pkg)), {pk}, pkg.string());
      CHECK(c.id_at_version() == "demo@1.0.0");
      bytes.push_back(0);
      CHECK_THROWS_AS(verify_package_signature(bytes, read_text(signature_path_for(pkg)), {pk}, pkg.string()),
                      std::runtime_error);
      bytes.pop_back();
    }
  }
}
