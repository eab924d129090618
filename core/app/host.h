// The host wiring: the skill registry, the skill manager and the host loop, with the
// Robot API served from personal data and a body. `marvin run --sim` uses the console
// body below and the owner's SQLite store (data::SqliteStore), or in-memory personal data
// when asked; with the store, the reminder Scheduler speaks due reminders through the
// same output as the skills (start_scheduler()).
#pragma once

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "app/host_phone.h"
#include "devices/body.h"
#include "home/config.h"
#include "home/home_service.h"
#include "skills/host_loop.h"
#include "data/clock.h"
#include "data/sqlite_store.h"
#include "skills/in_memory_personal_data.h"
#include "skills/manager.h"
#include "skills/registry.h"

namespace marvin::navigation {
class Navigator;
}  // namespace marvin::navigation

namespace marvin::app {

class SerialNavigation;
class SimHome;
class SkillReloader;
class SkillWatcher;
class HomeLink;

// Serialises lines written by several threads (the loop, a long task, the body).
class Console {
 public:
  explicit Console(std::function<void(std::string_view)> write_line);
  void line(std::string_view text);

 private:
  std::mutex mutex_;
  std::function<void(std::string_view)> write_line_;
};

// A body that shows what it would do: "[light: executing]", "[move forward, speed 120,
// 1500 ms]", "[stop]". Repeated identical light changes are shown once.
class ConsoleBody : public devices::Body {
 public:
  explicit ConsoleBody(Console& console) : console_(console) {}
  void move(devices::Direction direction, std::uint8_t speed,
            std::chrono::milliseconds duration) override;
  void stop() override;
  void tilt_head(int degrees) override;
  std::vector<devices::ScanPoint> latest_scan() override;
  void set_light(devices::Light light) override;

 private:
  Console& console_;
  std::mutex mutex_;
  std::optional<devices::Light> light_;
};

struct HostOptions {
  // Skills directories, loaded in order. The build's built-in skills come first unless
  // `builtin_skills` is false.
  std::vector<std::filesystem::path> skills_dirs;
  bool builtin_skills = true;
  std::string time_zone;                     // "" = the system's zone (UTC if unknown)
  std::optional<std::int64_t> fixed_now_ms;  // a stopped clock, for demos and tests
  // Personal data: in memory (nothing survives), or the SQLite store in `data_dir`
  // (empty: data::default_data_dir(), i.e. $MARVIN_DATA_DIR, else the XDG default).
  bool in_memory_data = false;
  std::filesystem::path data_dir;
  // Drive the body through this serial tty as well as showing it on the console: the
  // base's MCU (/dev/ttyACM0) or the pseudo-terminal link of `marvin-mcu-sim --link PATH`.
  // Empty: the console only.
  std::string mcu_tty;
  // The store's installed skills (app/installed_skills.h), loaded after `skills_dirs` when
  // the directory exists; no error when it does not. Empty: none.
  std::filesystem::path installed_skills_dir;
  // The simulated home (app/sim_home.h): with a world file and no mcu_tty, the body is the
  // simulated robot in that world and skills can go places; with mcu_tty, the world's floor
  // plan and start pose let skills go places on the serial base by dead reckoning.
  // Empty: the console body only, and no going places.
  std::filesystem::path world_file;
  double sim_speed = 1;       // simulated seconds per second
  std::uint64_t sim_seed = 1;
  std::filesystem::path show;  // keep this PNG of the floor plan up to date
  // The camera skills look through (Robot API 1.2; vision/cameras.h: "folder:DIR",
  // "video:FILE", "device:/dev/video0"). Empty: the simulated home's camera with a world file
  // (SimHome::camera()), else no camera (vision_* are unavailable).
  std::string camera;
  // Smart home over the home's MQTT broker (core/home): devices for the skills, Marvin's
  // activity and events on the bus. nullopt: no smart home.
  std::optional<home::HomeConfig> home;
  // The telephone (app/host_phone.h; the Robot API's phone calls): nullopt: none.
  std::optional<PhoneOptions> phone;
};

// Where this build put its built-in skills (<build>/skills).
std::filesystem::path builtin_skills_dir();
// The system's IANA time zone, or "UTC".
std::string system_time_zone();

class Host {
 public:
  // Wires everything; `console` receives the transcript ("Marvin: ..." and body lines).
  // Throws (naming the file) if the SQLite store cannot be opened (corrupt, newer schema).
  Host(HostOptions options, std::function<void(std::string_view)> write_line);
  ~Host();

  // Adds a runtime (e.g. Lua) before load().
  void add_runtime(std::unique_ptr<skills::SkillRuntime> runtime);
  // Loads every skills directory, after finishing any interrupted store operation in those
  // the store manages (Installer::recover()). Errors are in registry().errors().
  void load();
  // Skills installed, upgraded, rolled back or removed while running (SkillReloader): the
  // changes, one line each, also shown on the console as "[skill hello 1.0.0 loaded]". Runs
  // the reload now: call it on the loop thread while no long task runs, or before run().
  std::vector<std::string> reload_skills();
  // Asks for reload_skills() on the loop thread, between utterances and once no long task
  // runs. Any thread.
  void request_reload();
  // Watches the skills directories (SkillWatcher) and requests a reload on each change.
  // Throws std::runtime_error when the directories cannot be watched.
  void watch_skills();
  // With the SQLite store: announces what became due while the host was off, then runs
  // the reminder Scheduler on its own thread; due reminders are said through loop()
  // ("Reminder: take my pills", "You missed a reminder: ..."). Call once, before
  // loop().run(), on the thread that will run the loop. No-op with in-memory data.
  void start_scheduler();
  // The database file, or empty with in-memory data.
  std::filesystem::path data_path() const;

  skills::Registry& registry() { return *registry_; }
  skills::Manager& manager() { return *manager_; }
  skills::HostLoop& loop() { return *loop_; }
  devices::Body& body() { return *services_.body; }
  // The personal data the skills use (it tells the reminder scheduler of changes), and the
  // SQLite store behind it (null with in-memory data): what the web page changes and shows.
  data::PersonalData& data() { return *services_.data; }
  data::SqliteStore* store() { return store_.get(); }
  // The simulated home, with HostOptions::world_file; else nullptr.
  SimHome* sim_home() { return sim_home_.get(); }

  // For a voice front end (app/voice_host.h); set before loop().run(). `said` gets every
  // sentence Marvin says, after the console showed it, on the thread that said it.
  void on_said(std::function<void(std::string_view)> said) { said_ = std::move(said); }
  // A transcript line ("You: ..."), serialised with Marvin's. Any thread.
  void show(std::string_view line) { console_.line(line); }
  // Replaces the body the manager and the skills drive (a status light in front of the
  // console body); `body` must outlive its use. Before load(), or while nothing runs.
  void set_body(devices::Body& body) { services_.body = &body; }

  // With a smart home: the service (else null), where the robot is (the navigation's hook;
  // the config's room when unset or it answers ""), and events for the bus
  // ("intruder_alert", "call", ...; reminders are published by the host itself).
  home::HomeService* home() { return home_.get(); }
  void set_room_hook(std::function<std::string()> hook);
  void publish_event(const std::string& event_type, const std::string& text);
  // For the web page: the smart home as voice commands and skills use it (null without one),
  // and the navigator going places (the simulated home's or the serial base's floor plan;
  // null without a world file).
  skills::SmartHome* smart_home() { return services_.smarthome; }
  navigation::Navigator* navigator();
  // The telephone, when HostOptions::phone asked for one and baresip started; else null.
  HostPhone* phone() { return phone_.get(); }

 private:
  void wire_finding();
  HostOptions options_;
  Console console_;
  ConsoleBody body_;
  std::unique_ptr<devices::Body> serial_body_;  // with mcu_tty: the base over the serial link
  std::unique_ptr<devices::Body> mirrored_body_;  // with mcu_tty or a world: console + it
  std::unique_ptr<SimHome> sim_home_;             // with a world file
  std::unique_ptr<SerialNavigation> serial_navigation_;  // with mcu_tty and a world file
  std::unique_ptr<skills::InMemoryPersonalData> memory_;
  std::unique_ptr<data::SqliteStore> store_;
  std::unique_ptr<data::Clock> clock_;
  std::unique_ptr<data::PersonalData> data_;  // notifies the scheduler of reminder changes
  std::unique_ptr<skills::Eyes> eyes_;        // with a camera
  std::unique_ptr<skills::SightingLog> sightings_;  // finding (API 1.3)
  std::unique_ptr<skills::Guard> guard_;            // with a camera; stopped first
  struct Reminders;                           // the Scheduler and its io_context thread
  std::unique_ptr<Reminders> reminders_;
  skills::HostServices services_;
  std::unique_ptr<skills::HostLoop> loop_;
  std::function<void(std::string_view)> said_;
  std::unique_ptr<skills::Registry> registry_;
  std::unique_ptr<skills::Manager> manager_;
  std::vector<std::filesystem::path> watched_skills_dirs() const;  // skills_dirs + installed
  std::unique_ptr<SkillReloader> reloader_;
  std::atomic<bool> reload_requested_{false};
  std::unique_ptr<home::HomeService> home_;
  std::unique_ptr<HomeLink> home_link_;
  void start_home();
  std::unique_ptr<HostPhone> phone_;
  void start_phone();
  std::unique_ptr<SkillWatcher> watcher_;  // stopped first (declared last)
};

// A thread that posts each non-empty line of standard input (trailing blanks and CR
// removed) to host.loop() and closes the loop at end of input. The caller runs the loop;
// the destructor ends the thread also while the input is still open (a terminal after
// Ctrl-C, where nobody typed Ctrl-D).
class ConsoleReader {
 public:
  explicit ConsoleReader(Host& host);
  ~ConsoleReader();
  ConsoleReader(const ConsoleReader&) = delete;
  ConsoleReader& operator=(const ConsoleReader&) = delete;

 private:
  void read_lines(Host& host);
  int wake_[2] = {-1, -1};  // a byte on wake_[1] ends read_lines()
  std::thread thread_;
};

}  // namespace marvin::app
