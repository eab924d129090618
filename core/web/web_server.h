// The carer's web page: an HTTPS server (Boost.Beast) for the page in static/ and its JSON
// API (API.md), with live updates as Server-Sent Events.
//
// The server runs on its own thread with its own asio io_context: the host's loop is a
// condition-variable loop, not an asio one, so the page never waits for a skill and a skill
// never waits for the page. Every request is handled on that one thread; the store
// (data::SqliteStore) and the installer (store::Installer) are the same ones the CLI uses, so
// `marvin schedule list` and the page show the same reminders and apply the same rules.
//
// Security (README.md explains each choice): HTTPS only; a session cookie (Secure, HttpOnly,
// SameSite=Strict, expiring) after logging in with the password of `marvin web password`;
// every change carries the session's CSRF token; failed logins are rate-limited per client
// address; requests whose Origin is another site are refused; request bodies are capped and
// refused from their headers, before the body is read.
#pragma once

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "navigation/floor_map.h"
#include "store/minisign.h"
#include "web/auth.h"

namespace marvin::data {
class PersonalData;
class SqliteStore;
}  // namespace marvin::data

namespace marvin::skills {
class SmartHome;
}  // namespace marvin::skills

namespace marvin::web {

class LiveFeed;

struct WebOptions {
  // ADDR:PORT to listen on. Port 0: any free port (see WebServer::port()).
  std::string listen = "127.0.0.1:8443";
  // The password file, the sessions' secret and the generated certificate live here
  // (<data dir>/web by default, see web_state_dir()).
  std::filesystem::path state_dir;
  // The user's certificate and key (PEM). Both empty: <state_dir>/cert.pem and key.pem,
  // made on first start.
  std::filesystem::path cert_file;
  std::filesystem::path key_file;
  // Where the camera's photos are (intruder photos on the Events page); empty: the store's
  // folder's photos/ (<data dir>/photos, as the host saves them).
  std::filesystem::path photos_dir;
  // The page's HTML, CSS and JavaScript (default_static_dir()).
  std::filesystem::path static_dir;
  // The store's installed skills (the skills page); empty: none.
  std::filesystem::path skills_dir;
  // The host's check of a package before it is activated (app::validate_skill_for_host),
  // and the keys an uploaded package may be signed with (app::repository_keys).
  std::function<void(const std::filesystem::path&)> validate_skill;
  std::function<std::vector<store::PublicKey>()> trusted_keys;
  // The owner's time zone, for reminders added on the page and times shown.
  std::string time_zone = "UTC";
  // Largest skill package upload; other requests are capped at 64 KiB.
  std::size_t upload_limit = 32 * 1024 * 1024;
  std::chrono::seconds session_ttl = std::chrono::hours(12);
  int login_attempts_per_minute = 5;
  // What only the running robot has; null or empty under `marvin web serve`, and the pages
  // say so. The smart home the voice commands and the skills switch devices through
  // (app::HomeLink: the devices page); the home's floor plan (the world file's, as the
  // navigator has it) and where the robot is on it now (the home page). All must outlive
  // the server; robot_pose is called on the server's thread.
  skills::SmartHome* smart_home = nullptr;
  const navigation::FloorMap* floor_map = nullptr;
  std::function<std::optional<navigation::Pose>()> robot_pose;
  // The time sessions and the rate limit use (tests move it forward). Unset: steady_clock.
  std::function<Clock::time_point()> now;
};

// <data_dir>/web
std::filesystem::path web_state_dir(const std::filesystem::path& data_dir);
// <state_dir>/password
std::filesystem::path password_file(const std::filesystem::path& state_dir);
// Where this build put the page's files (<build>/web), or $MARVIN_WEB_ROOT when set.
std::filesystem::path default_static_dir();

class WebServer {
 public:
  // `data` is what reminders and contacts are changed through (the host's, which tells the
  // reminder scheduler), `store` the same SQLite file (events, people); `feed` may be null
  // (no host running: the status says so). All must outlive the server.
  WebServer(WebOptions options, data::PersonalData& data, data::SqliteStore& store, LiveFeed* feed);
  ~WebServer();
  WebServer(const WebServer&) = delete;
  WebServer& operator=(const WebServer&) = delete;

  // Loads or makes the certificate, binds and starts the server's thread. Throws
  // std::runtime_error naming the address or file that failed.
  void start();
  // Closes every connection and joins the thread. Idempotent.
  void stop();
  // The port listened on (after start()).
  std::uint16_t port() const;
  // "https://127.0.0.1:8443/"
  std::string url() const;
  // How many live (SSE) pages are open now. Any thread.
  std::size_t live_pages() const;

  struct Impl;  // the server's state (web_server.cpp)

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace marvin::web
