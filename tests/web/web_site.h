// The web tests' server: a real WebServer on 127.0.0.1 (ephemeral port, its own generated
// certificate) over a fresh SQLite file, a skills folder trusting a fresh key, and a clock
// the test moves forward.
#pragma once

#include <doctest/doctest.h>
#include <sodium.h>

#include <atomic>
#include <cstring>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "../app/test_skills.h"
#include "app/installed_skills.h"
#include "data/sqlite_store.h"
#include "store/installer.h"
#include "support/files.h"
#include "support/signed_package.h"
#include "web/auth.h"
#include "web/live.h"
#include "web/web_server.h"
#include "web_client.h"

namespace marvin::web::test {

namespace fs = std::filesystem;
using nlohmann::json;
using test_support::TempDir;

inline constexpr const char* kPassword = "correct horse battery";

inline std::string base64(const std::string& bytes) {
  std::string out(sodium_base64_encoded_len(bytes.size(), sodium_base64_VARIANT_ORIGINAL), '\0');
  sodium_bin2base64(out.data(), out.size(), reinterpret_cast<const unsigned char*>(bytes.data()),
                    bytes.size(), sodium_base64_VARIANT_ORIGINAL);
  out.resize(std::strlen(out.c_str()));
  return out;
}

// A server on a fresh data folder, a skills folder trusting `key`, and a clock the test
// moves forward.
struct Site {
  TempDir tmp;
  data::SqliteStore store{[this] {
    data::StoreOptions o;
    o.path = tmp / "data/marvin.db";
    return o;
  }()};
  LiveFeed feed;
  store::SecretKey key = store::generate_secret_key();
  std::atomic<std::int64_t> advanced_s{0};
  std::unique_ptr<WebServer> server;

  explicit Site(std::size_t upload_limit = 1024 * 1024,
                const std::function<void(WebOptions&)>& adjust = {}) {
    set_password(password_file(tmp / "data/web"), kPassword, HashCost::kMinimum);
    // The skills folder trusts `key`, as after `marvin skill repo-add`.
    test_support::write_text(
        tmp / "skills/.store/repositories.json",
        json{{"home", {{"path", "/nowhere"}, {"keys", {key.public_key().base64()}}}}}.dump());
    // A skills folder in use (its lock files made), so a refusal must leave it byte for byte.
    store::Installer(tmp / "skills").recover();
    WebOptions o;
    o.listen = "127.0.0.1:0";
    o.state_dir = tmp / "data/web";
    o.static_dir = fs::path(MARVIN_WEB_TEST_STATIC_DIR);
    o.skills_dir = tmp / "skills";
    o.validate_skill = app::validate_skill_for_host;
    o.trusted_keys = [dir = o.skills_dir] { return app::repository_keys(dir); };
    o.time_zone = "Europe/Berlin";
    o.upload_limit = upload_limit;
    o.session_ttl = std::chrono::minutes(30);
    o.now = [this] { return Clock::time_point(std::chrono::seconds(1000000 + advanced_s.load())); };
    if (adjust) adjust(o);
    server = std::make_unique<WebServer>(o, store, store, &feed);
    server->start();
  }
  Browser browser() { return Browser(server->port(), tmp / "data/web/cert.pem"); }
  Browser logged_in() {
    Browser b = browser();
    REQUIRE(b.login(kPassword).status == 200);
    return b;
  }
  // A signed package of a Lua skill, as `marvin skill pack --sign` makes it.
  fs::path package(const std::string& id, const std::string& version,
                   const std::string& permissions = "[]") {
    const fs::path src =
        app::test::lua_skill(tmp / "src", id, version, "Hi", "", R"({"min": "1.0"})", permissions);
    return test_support::pack_signed(src, tmp / "packages", key);
  }
  Reply upload(Browser& b, const fs::path& package, const std::string& name, bool approve = true) {
    return b.send(
        "POST", "/api/skills/install?file=" + name + (approve ? "&approve=1" : ""),
        test_support::read_text(package),
        {{"X-Marvin-Signature", base64(test_support::read_text(package.string() + ".minisig"))},
         {"Content-Type", "application/octet-stream"}});
  }
};

}  // namespace marvin::web::test
