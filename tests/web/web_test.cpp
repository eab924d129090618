// The carer's web page against a real server on 127.0.0.1 (an ephemeral port, its own
// generated certificate) and a real SQLite file: the API's operations, and every refusal
// with its status, its message and proof that nothing changed.
#include <doctest/doctest.h>
#include <sodium.h>

#include <atomic>

#include "../app/test_skills.h"
#include "app/installed_skills.h"
#include "data/recurrence.h"
#include "data/sqlite_store.h"
#include "store/installer.h"
#include "support/files.h"
#include "web/auth.h"
#include "web/live.h"
#include "web/tls.h"
#include "web/web_server.h"
#include "web_client.h"
#include "web_site.h"

namespace marvin::web {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using test::Browser;
using test::Reply;
using test::base64;
using test::kPassword;
using test::Site;
using test_support::TempDir;

const std::string kReminder =
    json{{"title", "take my pills"}, {"at", "2031-03-04T08:30"}, {"repeat", "daily"}}.dump();

TEST_CASE("web: login, then the page and the API; without a session only the login page") {
  Site site;
  Browser anonymous = site.browser();
  CHECK(anonymous.send("GET", "/login.html").status == 200);
  Reply page = anonymous.send("GET", "/");
  CHECK(page.status == 302);
  Reply api = anonymous.send("GET", "/api/reminders");
  CHECK(api.status == 401);
  CHECK(api.error() == "not logged in, or the session expired: log in at /login.html");

  Browser b = site.browser();
  Reply login = b.login(kPassword);
  REQUIRE(login.status == 200);
  CHECK(login.set_cookie.find("Secure") != std::string::npos);
  CHECK(login.set_cookie.find("HttpOnly") != std::string::npos);
  CHECK(login.set_cookie.find("SameSite=Strict") != std::string::npos);
  CHECK(login.set_cookie.find("Max-Age=1800") != std::string::npos);
  Reply index = b.send("GET", "/");
  CHECK(index.status == 200);
  CHECK(index.body.find("<title>Marvin</title>") != std::string::npos);
  CHECK(b.send("GET", "/api/session").json()["csrf"] == b.csrf);

  Reply out = b.send("POST", "/api/logout");
  CHECK(out.status == 200);
  CHECK(b.send("GET", "/api/reminders").status == 401);
}

TEST_CASE("web: a wrong password is refused and rate-limited per client") {
  Site site;
  Browser b = site.browser();
  for (int i = 0; i < 5; ++i) {
    Reply r = b.login("wrong password");
    CHECK(r.status == 401);
    CHECK(r.error() == "wrong password");
    CHECK(r.set_cookie.empty());
  }
  Reply limited = b.login(kPassword);  // even the right one, until the minute is over
  CHECK(limited.status == 429);
  CHECK(limited.error() == "too many failed logins from 127.0.0.1; try again in 60 s");
  CHECK(limited.set_cookie.empty());
  site.advanced_s += 61;
  CHECK(b.login(kPassword).status == 200);
}

TEST_CASE("web: reminders added, edited and deleted on the page are the CLI's reminders") {
  Site site;
  Browser b = site.logged_in();
  Reply added = b.send("POST", "/api/reminders", kReminder);
  REQUIRE(added.status == 201);
  CHECK(added.json()["next"] == "2031-03-04 08:30");
  CHECK(added.json()["repeat"] == "daily");
  CHECK(added.json()["time_zone"] == "Europe/Berlin");
  // What `marvin schedule list` prints from: the store's list.
  auto stored = site.store.list_reminders();
  REQUIRE(stored.size() == 1);
  CHECK(stored[0].title == "take my pills");
  CHECK(stored[0].created_by == "user");

  const std::string id = std::to_string(stored[0].id);
  Reply edited = b.send(
      "PUT", "/api/reminders/" + id,
      json{
          {"title", "take the blue pill"}, {"at", "2031-03-04T09:00"}, {"repeat", "weekly:mon,thu"}}
          .dump());
  REQUIRE(edited.status == 200);
  // The edit form starts from what is stored, in the form's own words.
  CHECK(edited.json()["repeat_spec"] == "weekly:mon,thu");
  CHECK(edited.json()["window"] == "");
  stored = site.store.list_reminders();
  REQUIRE(stored.size() == 1);
  CHECK(stored[0].title == "take the blue pill");
  CHECK(data::describe(stored[0].recurrence) == "weekly mon,thu");

  Reply listed = b.send("GET", "/api/reminders");
  REQUIRE(listed.json().size() == 1);
  CHECK(listed.json()[0]["title"] == "take the blue pill");

  Reply deleted = b.send("DELETE", "/api/reminders/" + std::to_string(stored[0].id));
  CHECK(deleted.status == 200);
  CHECK(site.store.list_reminders().empty());
  Reply again = b.send("DELETE", "/api/reminders/" + std::to_string(stored[0].id));
  CHECK(again.status == 404);
  CHECK(again.error() == "no active reminder with id " + std::to_string(stored[0].id));
}

TEST_CASE("web: a bad reminder names the field and adds nothing") {
  Site site;
  Browser b = site.logged_in();
  REQUIRE(b.send("POST", "/api/reminders", kReminder).status == 201);
  Reply bad_repeat =
      b.send("POST", "/api/reminders",
             json{{"title", "x"}, {"at", "2031-03-04T08:30"}, {"repeat", "fortnightly"}}.dump());
  CHECK(bad_repeat.status == 422);
  CHECK(bad_repeat.error() ==
        "repeat: unknown 'fortnightly' (expected once, daily, weekdays, weekly:mon,thu or "
        "every:MINUTES)");
  Reply bad_time =
      b.send("POST", "/api/reminders", json{{"title", "x"}, {"at", "tomorrow"}}.dump());
  CHECK(bad_time.status == 400);
  CHECK(bad_time.error().rfind("field 'at': ", 0) == 0);
  Reply no_title = b.send("POST", "/api/reminders", json{{"at", "2031-03-04T08:30"}}.dump());
  CHECK(no_title.status == 400);
  CHECK(no_title.error() == "field 'title': missing");
  Reply not_json = b.send("POST", "/api/reminders", "{title");
  CHECK(not_json.status == 400);
  CHECK(not_json.error().rfind("request body: not valid JSON", 0) == 0);
  // An edit that is refused leaves the reminder as it was.
  const auto id = site.store.list_reminders()[0].id;
  Reply bad_edit =
      b.send("PUT", "/api/reminders/" + std::to_string(id),
             json{{"title", "y"}, {"at", "2031-03-04T08:30"}, {"repeat", "weekly:funday"}}.dump());
  CHECK(bad_edit.status == 422);
  CHECK(bad_edit.error() == "repeat: unknown day 'funday' (expected mon,tue,wed,thu,fri,sat,sun)");
  auto stored = site.store.list_reminders();
  REQUIRE(stored.size() == 1);
  CHECK(stored[0].id == id);
  CHECK(stored[0].title == "take my pills");
}

TEST_CASE("web: contacts, and <script> in a name comes back as data") {
  Site site;
  Browser b = site.logged_in();
  const std::string name = "<script>alert('x')</script> Anna";
  Reply added = b.send(
      "POST", "/api/contacts",
      json{{"name", name}, {"relation", "daughter"}, {"phones", {"+49 30 1234"}}, {"emergency", 1}}
          .dump());
  REQUIRE(added.status == 201);
  Reply listed = b.send("GET", "/api/contacts");
  CHECK(listed.content_type == "application/json; charset=utf-8");
  REQUIRE(listed.json().size() == 1);
  CHECK(listed.json()[0]["name"] == name);  // the text as typed, never turned into markup
  CHECK(listed.json()[0]["emergency"] == 1);
  // The page puts names in with textContent only (no innerHTML anywhere in its script).
  CHECK(
      test_support::read_text(fs::path(MARVIN_WEB_TEST_STATIC_DIR) / "app.js").find("innerHTML") ==
      std::string::npos);

  const auto id = site.store.list_contacts()[0].id;
  Reply edited = b.send(
      "PUT", "/api/contacts/" + std::to_string(id),
      json{{"name", "Anna Schmidt"}, {"relation", "daughter"}, {"sip", {"sip:anna@example.org"}}}
          .dump());
  REQUIRE(edited.status == 200);
  auto contacts = site.store.list_contacts();
  REQUIRE(contacts.size() == 1);
  CHECK(contacts[0].name == "Anna Schmidt");
  CHECK(contacts[0].sip_uris == std::vector<std::string>{"sip:anna@example.org"});
  Reply bad = b.send("POST", "/api/contacts", json{{"name", "Bob"}, {"emergency", "first"}}.dump());
  CHECK(bad.status == 400);
  CHECK(bad.error() ==
        "field 'emergency': expected a whole number 0..99 (0: not an emergency contact)");
  CHECK(site.store.list_contacts().size() == 1);
  CHECK(b.send("DELETE", "/api/contacts/" + std::to_string(contacts[0].id)).status == 200);
  CHECK(site.store.list_contacts().empty());
}

TEST_CASE("web: a change without the session's CSRF token is refused and changes nothing") {
  Site site;
  Browser b = site.logged_in();
  const std::string csrf = b.csrf;
  b.no_csrf = true;
  Reply missing = b.send("POST", "/api/reminders", kReminder);
  CHECK(missing.status == 403);
  CHECK(missing.error() == "missing CSRF token (X-CSRF-Token header); nothing was changed");
  b.no_csrf = false;
  b.csrf = std::string(csrf.size(), 'a');
  Reply wrong = b.send("POST", "/api/reminders", kReminder);
  CHECK(wrong.status == 403);
  CHECK(wrong.error() == "wrong CSRF token (X-CSRF-Token header); nothing was changed");
  CHECK(site.store.list_reminders().empty());
  // Another session's token is as wrong as a made-up one.
  Browser other = site.logged_in();
  b.csrf = other.csrf;
  CHECK(b.send("POST", "/api/reminders", kReminder).status == 403);
  CHECK(site.store.list_reminders().empty());
}

TEST_CASE("web: an expired session is refused and changes nothing") {
  Site site;
  Browser b = site.logged_in();
  REQUIRE(b.send("GET", "/api/reminders").status == 200);
  site.advanced_s += 30 * 60 + 1;
  Reply expired = b.send("POST", "/api/reminders", kReminder);
  CHECK(expired.status == 401);
  CHECK(expired.error() == "not logged in, or the session expired: log in at /login.html");
  CHECK(site.store.list_reminders().empty());
  CHECK(b.send("GET", "/").status == 302);
}

TEST_CASE("web: a request from another origin is refused and changes nothing") {
  Site site;
  Browser b = site.logged_in();
  Reply r = b.send("POST", "/api/reminders", kReminder, {{"Origin", "https://evil.example"}});
  CHECK(r.status == 403);
  const std::string expected =
      "request from another origin (https://evil.example) refused; this "
      "page is https://127.0.0.1:" +
      std::to_string(site.server->port());
  CHECK(r.error() == expected);
  REQUIRE(b.send("POST", "/api/contacts", json{{"name", "Anna"}}.dump()).status == 201);
  const auto contact = std::to_string(site.store.list_contacts()[0].id);
  Reply fetch_site =
      b.send("DELETE", "/api/contacts/" + contact, "", {{"Sec-Fetch-Site", "cross-site"}});
  CHECK(fetch_site.status == 403);
  CHECK(fetch_site.error() ==
        "request from another origin (cross-site) refused; this page is "
        "https://127.0.0.1:" +
            std::to_string(site.server->port()));
  CHECK(site.store.list_contacts().size() == 1);
  Reply read = b.send("GET", "/api/contacts", "", {{"Sec-Fetch-Site", "cross-site"}});
  CHECK(read.status == 403);  // another site's script may not read the data either
  // A link on another site may open the page itself.
  CHECK(b.send("GET", "/", "", {{"Sec-Fetch-Site", "cross-site"}}).status == 200);
  Reply login = b.send("POST", "/api/login", json{{"password", kPassword}}.dump(),
                       {{"Origin", "http://127.0.0.1"}});
  CHECK(login.status == 403);
  CHECK(login.set_cookie.empty());
  CHECK(site.store.list_reminders().empty());
}

TEST_CASE("web: a 100 MB upload is refused from its headers, before the body is sent") {
  Site site;  // upload limit 1 MiB
  Browser b = site.logged_in();
  const auto before = test_support::snapshot(site.tmp / "skills");
  test::Connection c(site.server->port(), site.tmp / "data/web/cert.pem");
  // Only the head: the server answers without waiting for the 100 MB.
  c.write(
      "POST /api/skills/install?file=big-1.0.0.mskill&approve=1 HTTP/1.1\r\nHost: 127.0.0.1\r\n"
      "Cookie: " +
      b.cookie + "\r\nX-CSRF-Token: " + b.csrf + "\r\nContent-Length: 104857600\r\n\r\n");
  Reply r = c.read_reply();
  CHECK(r.status == 413);
  CHECK(r.error() == "request body too large: 104857600 bytes, at most 1048576 bytes here");
  CHECK(test_support::snapshot(site.tmp / "skills") == before);
  const bool no_upload_kept =
      !fs::exists(site.tmp / "data/web/uploads") || fs::is_empty(site.tmp / "data/web/uploads");
  CHECK(no_upload_kept);
  // Other requests are capped lower.
  Reply contact = b.send("POST", "/api/contacts", json{{"name", std::string(70000, 'a')}}.dump());
  CHECK(contact.status == 413);
  CHECK(contact.error().rfind("request body too large: 70", 0) == 0);
  CHECK(site.store.list_contacts().empty());
}

TEST_CASE("web: skills: install a signed upload, upgrade, roll back, remove") {
  Site site;
  Browser b = site.logged_in();
  const fs::path v1 = site.package("hello", "1.0.0", R"(["storage"])");
  Reply unapproved = site.upload(b, v1, "hello-1.0.0.mskill", false);
  CHECK(unapproved.status == 409);
  CHECK(unapproved.error().find("permissions not approved (storage)") != std::string::npos);
  CHECK(b.send("GET", "/api/skills").json().empty());

  Reply installed = site.upload(b, v1, "hello-1.0.0.mskill");
  REQUIRE(installed.status == 201);
  CHECK(installed.json()["outcome"] == "installed");
  CHECK(installed.json()["permissions"] == json{"storage"});
  const fs::path v2 = site.package("hello", "1.1.0", R"(["storage"])");
  Reply upgraded = site.upload(b, v2, "hello-1.1.0.mskill");
  REQUIRE(upgraded.status == 201);
  CHECK(upgraded.json()["outcome"] == "upgraded");
  json list = b.send("GET", "/api/skills").json();
  REQUIRE(list.size() == 1);
  CHECK(list[0]["version"] == "1.1.0");
  CHECK(list[0]["previous"] == "1.0.0");

  Reply rolled = b.send("POST", "/api/skills/hello/rollback");
  REQUIRE(rolled.status == 200);
  CHECK(rolled.json()["version"] == "1.0.0");
  CHECK(b.send("DELETE", "/api/skills/hello").status == 200);
  CHECK(b.send("GET", "/api/skills").json().empty());
  Reply gone = b.send("DELETE", "/api/skills/hello");
  CHECK(gone.status == 404);
  CHECK(gone.error() == "skill 'hello' is not installed");
}

TEST_CASE("web: an upload named with ../, unsigned or signed by a stranger is refused") {
  Site site;
  Browser b = site.logged_in();
  const fs::path v1 = site.package("hello", "1.0.0");
  const auto before = test_support::snapshot(site.tmp / "skills");

  Reply dots = site.upload(b, v1, "../../hello-1.0.0.mskill");
  CHECK(dots.status == 400);
  CHECK(dots.error() ==
        "file name '../../hello-1.0.0.mskill' refused: expected a plain name ending "
        "in .mskill, like hello-1.0.0.mskill (no folders, no '..')");
  Reply encoded = site.upload(b, v1, "..%2Fhello-1.0.0.mskill");
  CHECK(encoded.status == 400);
  CHECK(encoded.error().rfind("file name '../hello-1.0.0.mskill' refused", 0) == 0);
  CHECK(!fs::exists(site.tmp / "data/hello-1.0.0.mskill"));
  CHECK(!fs::exists(site.tmp / "hello-1.0.0.mskill"));

  Reply unsigned_upload = b.send("POST", "/api/skills/install?file=hello-1.0.0.mskill&approve=1",
                                 test_support::read_text(v1));
  CHECK(unsigned_upload.status == 400);
  CHECK(unsigned_upload.error() ==
        "X-Marvin-Signature: missing; send the package's .minisig file with it");

  // Signed with a key the skills folder does not trust.
  const fs::path src = app::test::lua_skill(site.tmp / "stranger", "hello", "1.0.0", "Hi");
  const fs::path strange =
      test_support::pack_signed(src, site.tmp / "stranger-packages", store::generate_secret_key());
  Reply stranger = site.upload(b, strange, "hello-1.0.0.mskill");
  CHECK(stranger.status == 422);
  CHECK(stranger.error().find("hello-1.0.0.mskill") != std::string::npos);
  CHECK(stranger.error().find("uploads") == std::string::npos);  // no server folder in messages
  CHECK(test_support::snapshot(site.tmp / "skills") == before);
  CHECK(fs::is_empty(site.tmp / "data/web/uploads"));
}

TEST_CASE("web: an open page gets the status, conversation turns and new events live") {
  Site site;
  Browser b = site.logged_in();
  auto live = b.open_live();
  auto hello = live->next_event();
  CHECK(hello.first == "hello");
  CHECK(json::parse(hello.second)["running"] == true);
  // The server counts the page once it has sent the hello.
  site.feed.console_line("[light: executing]");
  auto status = live->next_event();
  CHECK(status.first == "status");
  CHECK(json::parse(status.second)["light"] == "executing");
  site.feed.console_line("Marvin: It is 8 o'clock.");
  auto turn = live->next_event();
  CHECK(turn.first == "turn");
  CHECK(json::parse(turn.second) == json{{"who", "Marvin"}, {"text", "It is 8 o'clock."}});
  site.store.log_event("intruder_alert", "security", "someone in the hall");
  auto event = live->next_event();
  CHECK(event.first == "event");
  CHECK(json::parse(event.second)["message"] == "someone in the hall");
  CHECK(json::parse(event.second)["kind"] == "intruder_alert");
  // A reminder the scheduler retires as missed is an event written in its own transaction:
  // it comes the same way, with nothing polling the log.
  data::Reminder once;
  once.title = "water the plants";
  once.time_zone = "Europe/Berlin";
  once.first_fire_utc_ms = data::local_to_utc_ms("2031-01-01T08:00", once.time_zone);
  once.created_by = "user";
  const auto once_id = site.store.add_reminder(once);
  REQUIRE(site.store.advance_reminder(once_id, once.first_fire_utc_ms, once.first_fire_utc_ms,
                                      std::nullopt, "reminder_missed", "water the plants"));
  auto missed = live->next_event();
  CHECK(missed.first == "event");
  CHECK(json::parse(missed.second)["kind"] == "reminder_missed");
  // Another writer on the same file (as `marvin people forget` in a shell, another process):
  // the server sees the database's journal change and reads the new event.
  {
    data::StoreOptions other;
    other.path = site.store.path();
    data::SqliteStore(other).log_event("face_forgotten", "cli", "Bob: 1 face embedding(s) removed");
  }
  auto from_other = live->next_event();
  CHECK(from_other.first == "event");
  CHECK(json::parse(from_other.second)["source"] == "cli");
  // A change made on another page tells this one.
  REQUIRE(b.send("POST", "/api/reminders", kReminder).status == 201);
  auto changed = live->next_event();
  CHECK(changed.first == "changed");
  CHECK(json::parse(changed.second)["what"] == "reminders");
  CHECK(site.server->live_pages() == 1);
  // Today's status shows the same.
  json today = b.send("GET", "/api/status").json();
  CHECK(today["live"]["light"] == "executing");
  CHECK(today["next_reminders"].size() == 1);
  CHECK(today["recent_events"][2]["message"] == "someone in the hall");
}

TEST_CASE("web: a password shorter than 8 characters is refused and nothing is stored") {
  TempDir tmp;
  const fs::path file = password_file(tmp / "web");
  CHECK_THROWS_WITH_AS(set_password(file, "short", HashCost::kMinimum),
                       "the password must have at least 8 characters (it has 5)",
                       std::runtime_error);
  CHECK(!fs::exists(file));
  CHECK(!check_password(file, "short"));
  set_password(file, "long enough", HashCost::kMinimum);
  CHECK_THROWS_AS(set_password(file, "short", HashCost::kMinimum), std::runtime_error);
  CHECK(check_password(file, "long enough"));  // the old one still holds
  CHECK(test_support::read_text(file).find("long enough") == std::string::npos);  // only a hash
  CHECK(test_support::read_text(file).rfind("$argon2id$", 0) == 0);
}

TEST_CASE("web: the user's own certificate is used, and a missing key file is named") {
  TempDir mine;
  make_self_signed_certificate(mine / "site.pem", mine / "site.key", {"127.0.0.1"});
  Site site(1024 * 1024, [&](WebOptions& o) {
    o.cert_file = mine / "site.pem";
    o.key_file = mine / "site.key";
  });
  CHECK(!fs::exists(site.tmp / "data/web/cert.pem"));  // none made
  Browser b(site.server->port(), mine / "site.pem");   // trusts only the user's certificate
  CHECK(b.login(kPassword).status == 200);

  WebOptions o;
  o.listen = "127.0.0.1:0";
  o.state_dir = site.tmp / "other";
  o.cert_file = mine / "site.pem";
  o.key_file = mine / "missing.key";
  WebServer broken(o, site.store, site.store, nullptr);
  const std::string missing_key = (mine / "missing.key").string();
  CHECK_THROWS_WITH_AS(broken.start(), doctest::Contains(missing_key.c_str()), std::runtime_error);
  o.key_file.clear();
  WebServer half(o, site.store, site.store, nullptr);
  CHECK_THROWS_WITH_AS(half.start(),
                       "web certificate: give both the certificate and its key, or neither",
                       std::runtime_error);
  o.cert_file.clear();
  o.listen = "127.0.0.1";
  WebServer no_port(o, site.store, site.store, nullptr);
  CHECK_THROWS_WITH_AS(no_port.start(),
                       "web listen address '127.0.0.1' is not ADDR:PORT (e.g. 127.0.0.1:8443 or "
                       "0.0.0.0:8443)",
                       std::runtime_error);
}

}  // namespace
}  // namespace marvin::web
