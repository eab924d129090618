#include "app/host.h"
#include "app/guard_schedule.h"
#include "app/sim_home.h"
#include "app/store_sightings.h"

#include "devices/serial_body.h"

#include <date/tz.h>
#include <fcntl.h>
#include <poll.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <boost/asio/executor_work_guard.hpp>
#include <boost/asio/io_context.hpp>
#include <iostream>
#include <map>
#include <stdexcept>
#include <thread>

#include "data/scheduler.h"
#include "devices/serial_body.h"

#include "app/home_link.h"
#include "app/installed_skills.h"
#include "home/home_service.h"
#include "app/skill_reloader.h"
#include "app/skill_watcher.h"
#include "common/log.h"
#include "store/installer.h"
#include "vision/vision_eyes.h"
#ifdef MARVIN_HAVE_LUA
#include "scripting/lua_runtime.h"
#endif

#ifndef MARVIN_BUILTIN_SKILLS_DIR
#define MARVIN_BUILTIN_SKILLS_DIR "skills"
#endif

namespace marvin::app {

Console::Console(std::function<void(std::string_view)> write_line)
    : write_line_(std::move(write_line)) {}

void Console::line(std::string_view text) {
  std::lock_guard lock(mutex_);
  write_line_(text);
}

void ConsoleBody::move(devices::Direction direction, std::uint8_t speed,
                       std::chrono::milliseconds duration) {
  static const char* names[] = {"forward", "backward", "left", "right"};
  console_.line(std::string("[move ") + names[static_cast<int>(direction)] + ", speed " +
                std::to_string(speed) + ", " + std::to_string(duration.count()) + " ms]");
}

void ConsoleBody::stop() { console_.line("[stop]"); }

void ConsoleBody::tilt_head(int degrees) {
  console_.line("[head tilt " + std::to_string(degrees) + " degrees]");
}

std::vector<devices::ScanPoint> ConsoleBody::latest_scan() {
  // An empty room: nothing closer than the sonar's range, straight ahead to straight up.
  std::int64_t now = std::chrono::duration_cast<std::chrono::milliseconds>(
                         std::chrono::steady_clock::now().time_since_epoch())
                         .count();
  std::vector<devices::ScanPoint> scan;
  for (int angle = 0; angle <= 120; angle += 10)
    scan.push_back({static_cast<double>(angle), 2.5, now});
  return scan;
}

void ConsoleBody::set_light(devices::Light light) {
  {
    std::lock_guard lock(mutex_);
    if (light_ == light) return;
    light_ = light;
  }
  static const char* names[] = {"off", "awaiting (red)", "listening (green)", "executing (yellow)"};
  console_.line(std::string("[light: ") + names[static_cast<int>(light)] + "]");
}

namespace {

// Forwards to the real store and tells the scheduler when reminders changed.
class NotifyingData final : public data::PersonalData {
 public:
  NotifyingData(data::PersonalData& inner, std::function<void()> changed)
      : inner_(inner), changed_(std::move(changed)) {}

  std::int64_t add_reminder(const data::Reminder& reminder) override {
    std::int64_t id = inner_.add_reminder(reminder);
    changed_();
    return id;
  }
  std::vector<data::Reminder> reminders_between(std::int64_t from_utc_ms,
                                                std::int64_t to_utc_ms) override {
    return inner_.reminders_between(from_utc_ms, to_utc_ms);
  }
  std::vector<data::Reminder> list_reminders() override { return inner_.list_reminders(); }
  std::optional<data::Reminder> get_reminder(std::int64_t id) override {
    return inner_.get_reminder(id);
  }
  bool remove_reminder(std::int64_t id) override { return notify(inner_.remove_reminder(id)); }
  bool snooze_reminder(std::int64_t id, std::int64_t until_utc_ms) override {
    return notify(inner_.snooze_reminder(id, until_utc_ms));
  }
  bool complete_reminder(std::int64_t id) override {
    return notify(inner_.complete_reminder(id));
  }
  std::int64_t add_contact(const data::Contact& contact) override {
    return inner_.add_contact(contact);
  }
  std::vector<data::Contact> find_contacts(std::string_view name_or_alias) override {
    return inner_.find_contacts(name_or_alias);
  }
  std::vector<data::Contact> list_contacts() override { return inner_.list_contacts(); }
  bool remove_contact(std::int64_t id) override { return inner_.remove_contact(id); }
  std::vector<data::Person> list_people() override { return inner_.list_people(); }
  std::optional<std::string> storage_get(std::string_view skill_id,
                                         std::string_view key) override {
    return inner_.storage_get(skill_id, key);
  }
  void storage_set(std::string_view skill_id, std::string_view key,
                   std::string_view value) override {
    inner_.storage_set(skill_id, key, value);
  }
  bool storage_remove(std::string_view skill_id, std::string_view key) override {
    return inner_.storage_remove(skill_id, key);
  }
  void log_event(std::string_view kind, std::string_view source,
                 std::string_view message) override {
    inner_.log_event(kind, source, message);
  }

 private:
  bool notify(bool changed) {
    if (changed) changed_();
    return changed;
  }
  data::PersonalData& inner_;
  std::function<void()> changed_;
};

}  // namespace

struct Host::Reminders {
  boost::asio::io_context io;
  std::unique_ptr<data::Scheduler> scheduler;
  std::optional<boost::asio::executor_work_guard<boost::asio::io_context::executor_type>> work;
  std::thread thread;
  std::atomic<bool> running{false};
  // The reminder announced most recently (0: none yet): what "done" and "snooze" refer to.
  // Written by the scheduler's thread, read by skills' threads (schedule_last_fired).
  std::atomic<std::int64_t> last_fired{0};

  ~Reminders() {
    work.reset();
    io.stop();
    if (thread.joinable()) thread.join();
    scheduler.reset();
  }
};

std::filesystem::path builtin_skills_dir() { return MARVIN_BUILTIN_SKILLS_DIR; }

std::string system_time_zone() {
  try {
    return date::current_zone()->name();
  } catch (const std::exception&) {
    return "UTC";
  }
}

namespace {

// Shows every body command on the console and sends it to the serial base; the obstacle
// scan comes from the base, whose sonar is real (or simulated by marvin-mcu-sim).
class MirroredBody : public devices::Body {
 public:
  MirroredBody(devices::Body& shown, devices::Body& driven) : shown_(shown), driven_(driven) {}
  void move(devices::Direction direction, std::uint8_t speed,
            std::chrono::milliseconds duration) override {
    shown_.move(direction, speed, duration);
    driven_.move(direction, speed, duration);
  }
  void stop() override {
    shown_.stop();
    driven_.stop();
  }
  void tilt_head(int degrees) override {
    shown_.tilt_head(degrees);
    driven_.tilt_head(degrees);
  }
  std::vector<devices::ScanPoint> latest_scan() override { return driven_.latest_scan(); }
  void set_light(devices::Light light) override {
    shown_.set_light(light);
    driven_.set_light(light);
  }

 private:
  devices::Body& shown_;
  devices::Body& driven_;
};

}  // namespace

Host::Host(HostOptions options, std::function<void(std::string_view)> write_line)
    : options_(std::move(options)), console_(std::move(write_line)), body_(console_) {
  if (options_.fixed_now_ms) {
    clock_ = std::make_unique<data::ManualClock>(*options_.fixed_now_ms);
  }
  data::PersonalData* inner = nullptr;
  if (options_.in_memory_data) {
    // Stamped by the host's clock, set below before anything can log.
    memory_ = std::make_unique<skills::InMemoryPersonalData>(
        [this] { return services_.now_ms ? services_.now_ms() : skills::system_now_ms(); });
    inner = memory_.get();
  } else {
    data::StoreOptions store;
    store.path = data::database_path(options_.data_dir.empty() ? data::default_data_dir()
                                                               : options_.data_dir);
    store.clock = clock_.get();
    store_ = std::make_unique<data::SqliteStore>(std::move(store));
    inner = store_.get();
  }
  reminders_ = std::make_unique<Reminders>();
  data_ = std::make_unique<NotifyingData>(*inner, [this] {
    if (reminders_->running.load()) reminders_->scheduler->reminders_changed();
  });
  services_.data = data_.get();
  services_.body = &body_;
  services_.last_fired_reminder = [r = reminders_.get()]() -> std::optional<std::int64_t> {
    std::int64_t id = r->last_fired.load();
    if (id == 0) return std::nullopt;
    return id;
  };
  if (!options_.mcu_tty.empty()) {
    auto serial = std::make_unique<devices::SerialBody>(options_.mcu_tty);
    // Wait for the base once, so the first command of a session is not dropped; the link
    // keeps retrying in the background if the base is not there yet.
    constexpr std::chrono::seconds kBaseWait{5};
    if (serial->wait_connected(kBaseWait)) {
      console_.line("[base: connected on " + options_.mcu_tty + "]");
    } else {
      console_.line("[base: not connected on " + options_.mcu_tty + " after " +
                    std::to_string(kBaseWait.count()) + " s; still trying]");
    }
    if (!options_.world_file.empty()) {
      serial_navigation_ = std::make_unique<SerialNavigation>(options_.world_file, *serial);
      services_.going_places = &serial_navigation_->navigator();
    }
    serial_body_ = std::move(serial);
    mirrored_body_ = std::make_unique<MirroredBody>(body_, *serial_body_);
    services_.body = mirrored_body_.get();
  } else if (!options_.world_file.empty()) {
    SimHomeOptions sim;
    sim.world_file = options_.world_file;
    sim.speed = options_.sim_speed;
    sim.seed = options_.sim_seed;
    sim.show = options_.show;
    sim_home_ = std::make_unique<SimHome>(sim, [this](std::string_view line) { console_.line(line); });
    mirrored_body_ = std::make_unique<MirroredBody>(body_, sim_home_->body());
    services_.body = mirrored_body_.get();
    services_.going_places = &sim_home_->navigator();
  }
  const auto data_dir =
      store_ ? store_->path().parent_path() : std::filesystem::temp_directory_path();
  if (!options_.camera.empty()) {
    eyes_ = std::make_unique<vision::VisionEyes>(options_.camera, store_.get(), data_dir / "photos");
    services_.eyes = eyes_.get();
  } else if (sim_home_) {
    // No --camera in the simulated home: skills look through the robot's simulated head
    // camera. VisionEyes reads it under its own lock; each frame takes the pose under the
    // runner's lock, so skill threads never race the simulation thread.
    eyes_ =
        std::make_unique<vision::VisionEyes>([home = sim_home_.get()] { return home->camera(); },
                                             "simulated camera", store_.get(), data_dir / "photos");
    services_.eyes = eyes_.get();
  }
  services_.time_zone = options_.time_zone.empty() ? system_time_zone() : options_.time_zone;
  if (options_.fixed_now_ms) {
    std::int64_t now = *options_.fixed_now_ms;
    services_.now_ms = [now] { return now; };
  } else {
    services_.now_ms = skills::system_now_ms;
  }
  loop_ = std::make_unique<skills::HostLoop>(
      [this](std::string_view text) {
        if (home_) home_->publish_activity("speaking");
        console_.line("Marvin: " + std::string(text));
        if (said_) said_(text);
        if (home_) home_->publish_activity("listening");
      });
  registry_ = std::make_unique<skills::Registry>(services_);
#ifdef MARVIN_HAVE_LUA
  registry_->add_runtime(std::make_unique<scripting::LuaRuntime>());
#endif
  manager_ = std::make_unique<skills::Manager>(*registry_, *loop_);
  services_.user = manager_.get();
  loop_->attach(*manager_, registry_->interpreter());
  reloader_ = std::make_unique<SkillReloader>(*registry_);
  wire_finding();
  if (options_.home) start_home();
  if (options_.phone) start_phone();
  // Skill timers (marvin.after) run on the loop, never while a long task runs.
  loop_->set_timers(skills::HostLoop::Timers{
      [this]() -> std::optional<std::int64_t> {
        if (manager_->busy()) return std::nullopt;
        if (reload_requested_.load()) return services_.now_ms();  // due now
        std::optional<std::int64_t> next;
        for (const auto& skill : registry_->skills()) {
          if (!skill->instance) continue;
          std::optional<std::int64_t> due = skill->instance->next_timer_ms();
          if (due && (!next || *due < *next)) next = due;
        }
        return next;
      },
      [this](std::int64_t now) {
        if (!manager_->idle()) return;
        if (reload_requested_.exchange(false)) reload_skills();
        for (const auto& skill : registry_->skills()) {
          if (!skill->instance) continue;
          std::optional<std::int64_t> due = skill->instance->next_timer_ms();
          if (due && *due <= now) skill->instance->poll(now);
        }
      },
      services_.now_ms});
}

Host::~Host() {
  watcher_.reset();    // no reload requests from now on
  if (reminders_) {    // the scheduler's thread switches guard_ (a guard schedule): stop it
    reminders_->work.reset();
    reminders_->io.stop();
    if (reminders_->thread.joinable()) reminders_->thread.join();
  }
  guard_.reset();      // its thread looks through eyes_ and speaks through loop_
  manager_.reset();    // joins a running task first
  phone_.reset();      // announces through the loop, logs to the data
  home_link_.reset();
  home_.reset();       // says "offline" on the bus
  reminders_.reset();  // stops the scheduler's thread
  registry_.reset();  // then the skills go
  serial_navigation_.reset();
  mirrored_body_.reset();
  eyes_.reset();  // the simulated camera reads the sim's world
  sim_home_.reset();
}

// Finding and guarding (issue 22, API 1.3): sightings in the store (in memory with
// --in-memory), guard mode on the camera, the event log for "who came while I was out?".
void Host::wire_finding() {
  if (store_) {
    sightings_ = std::make_unique<StoreSightingLog>(*store_);
    services_.events = [store = store_.get()](std::string_view kind, std::int64_t since) {
      std::vector<skills::HostServices::LoggedEvent> out;
      for (const data::Event& e : store->recent_events(200)) {
        if (e.time_utc_ms < since) break;
        if (kind.empty() || e.kind == kind) out.push_back({e.kind, e.message, e.time_utc_ms});
      }
      return out;
    };
  } else {
    sightings_ = std::make_unique<skills::InMemorySightingLog>(services_.now_ms);
    if (memory_) {
      services_.events = [memory = memory_.get()](std::string_view kind, std::int64_t since) {
        std::vector<skills::HostServices::LoggedEvent> out;
        for (const auto& e : memory->recent_events(kind, since)) {
          out.push_back({e.kind, e.message, e.time_ms});
        }
        return out;
      };
    }
  }
  services_.sightings = sightings_.get();
  if (!eyes_) return;
  skills::GuardOptions guard;
  if (services_.going_places) guard.time_scale = services_.going_places->time_scale();
  if (store_) {  // `marvin guard status|off` from another process (cli_guard.cpp)
    guard.changed = [this](const skills::GuardState& s) {
      store_->storage_set(skills::kGuardStorageId, skills::kGuardStateKey,
                          skills::guard_state_json(s));
      if (!s.on && s.by == skills::kOffByCommandLine) {
        loop_->say("Guard mode is off: it was turned off from the command line.");
      }
    };
    guard.off_requested = [this](const skills::GuardState& s) {
      auto request = store_->storage_get(skills::kGuardStorageId, skills::kGuardOffKey);
      return request && *request == std::to_string(s.since_ms);
    };
  }
  guard_ = std::make_unique<skills::Guard>(
      *eyes_, services_.going_places, services_.now_ms,
      [this](const std::string& photo, const std::string& who) {
        std::string where;
        if (services_.going_places) {
          if (auto room = services_.going_places->where_am_i()) where = " in the " + *room;
        }
        const std::string message = "Intruder alert: I see " + who + where + "." +
                                    (photo.empty() ? "" : " Photo: " + photo);
        try {
          data_->log_event("intruder", "guard", message);
        } catch (const std::exception& e) {
          log(LogLevel::kWarning, "guard", std::string("event not logged: ") + e.what());
        }
        publish_event("intruder", message);
        loop_->say("Intruder alert! I see " + who + where + ". I took a photo and told your carer.");
      },
      guard);
  services_.guard = guard_.get();
}

void Host::add_runtime(std::unique_ptr<skills::SkillRuntime> runtime) {
  registry_->add_runtime(std::move(runtime));
}

std::filesystem::path Host::data_path() const {
  return store_ ? store_->path() : std::filesystem::path();
}

void Host::start_scheduler() {
  if (!store_ || reminders_->scheduler) return;
  const data::Clock& clock =
      clock_ ? *clock_ : static_cast<const data::Clock&>(data::SystemClock::instance());
  reminders_->scheduler = std::make_unique<data::Scheduler>(
      reminders_->io, *store_, clock, [this](const data::Firing& firing) {
        // A guard schedule's reminder switches guard mode instead (guard_schedule.h).
        if (auto said = apply_guard_firing(firing.reminder, guard_.get())) {
          if (!said->empty()) loop_->say(*said);
          return;
        }
        reminders_->last_fired.store(firing.reminder.id);
        publish_event(firing.missed ? "reminder_missed" : "reminder_fired", firing.reminder.title);
        loop_->say(firing.missed ? "You missed a reminder: " + firing.reminder.title
                                 : "Reminder: " + firing.reminder.title);
      });
  // The io_context is not running yet, so this thread stands in for it: what was due
  // while the host was off is said before the first utterance is taken.
  data::StartupReport report = reminders_->scheduler->start();
  if (!report.listed.empty()) {
    std::string titles;
    for (const data::MissedReminder& m : report.listed) {
      if (guard_switch(m.reminder)) continue;  // a guard schedule's: nothing to tell
      titles += (titles.empty() ? "" : ", ") + m.reminder.title;
      reminders_->last_fired.store(m.reminder.id);
    }
    if (!titles.empty()) loop_->say("While I was off, you missed: " + titles);
  }
  reminders_->work.emplace(reminders_->io.get_executor());
  reminders_->running.store(true);
  reminders_->thread = std::thread([r = reminders_.get()] { r->io.run(); });
}

void Host::start_home() {
  home_ = std::make_unique<home::HomeService>(*options_.home);
  if (store_) {
    std::map<std::string, std::string> aliases;
    for (auto& [alias, device] : store_->device_aliases()) aliases[alias] = device;
    home_->set_aliases(std::move(aliases));
  }
  if (options_.home->commands) {
    // Only the documented topics reach here (marvin/<site>/command/say|utterance).
    home_->on_command([this](const std::string& name, const std::string& payload) {
      if (name == "say") loop_->say(payload);
      if (name == "utterance") loop_->post(payload);
    });
  }
  home_link_ = std::make_unique<HomeLink>(*home_);
  services_.smarthome = home_link_.get();
  // "Turn on the light" means the light of the room the robot is in, when it knows (the
  // navigator: the simulated home, or a floor plan on the serial base); else the config's.
  if (navigation::GoingPlaces* places = services_.going_places) {
    home_->set_room_hook([places, fallback = options_.home->room] {
      return places->where_am_i().value_or(fallback);
    });
  }
  home_->start();
  // Wait for the broker once (what it retained: the devices), so the first request of a
  // session finds them; the service keeps retrying in the background otherwise.
  constexpr std::chrono::seconds kBrokerWait{3};
  const auto& b = options_.home->broker;
  const std::string where = b.host + ":" + std::to_string(b.port);
  if (home_->settle(kBrokerWait)) {
    console_.line("[home: " + std::to_string(home_->devices().size()) + " devices on " + where +
                  "]");
  } else {
    console_.line("[home: broker " + where + " not reachable after " +
                  std::to_string(kBrokerWait.count()) + " s; still trying]");
  }
}

void Host::start_phone() {
  PhoneLinkHooks hooks;
  hooks.announce = [this](const std::string& text) { loop_->say(text); };
  hooks.log_event = [this](const std::string& kind, const std::string& text) {
    data_->log_event(kind, "phone", text);
    publish_event(kind, text);
  };
  phone_ = std::make_unique<HostPhone>(*options_.phone, *data_, std::move(hooks));
  services_.telephone = phone_->link();
  // "Stop" during a call hangs up, like "hang up", unless it stops another skill's task
  // (the robot driving somewhere while the owner is on the phone).
  manager_->on_stop([link = phone_->link()](const std::string& running) -> std::string {
    if (!link || !(running.empty() || running == "phone") || !link->hang_up()) return {};
    return "OK, I hung up.";
  });
}

navigation::Navigator* Host::navigator() {
  if (sim_home_) return &sim_home_->navigator();
  if (serial_navigation_) return &serial_navigation_->navigator();
  return nullptr;
}

void Host::set_room_hook(std::function<std::string()> hook) {
  if (home_) home_->set_room_hook(std::move(hook));
}

void Host::publish_event(const std::string& event_type, const std::string& text) {
  if (home_) home_->publish_event(event_type, text);
}

namespace {

// Finishes an install, upgrade or removal another process left half done (store/README.md).
void recover_store(const std::filesystem::path& dir) {
  if (!is_store_directory(dir)) return;
  try {
    store::Installer(dir).recover();
  } catch (const std::exception& e) {
    log(LogLevel::kWarning, "skills", "cannot recover " + dir.string() + ": " + e.what());
  }
}

}  // namespace

std::vector<std::filesystem::path> Host::watched_skills_dirs() const {
  std::vector<std::filesystem::path> dirs = options_.skills_dirs;
  if (!options_.installed_skills_dir.empty()) dirs.push_back(options_.installed_skills_dir);
  return dirs;
}

void Host::load() {
  if (options_.builtin_skills) registry_->load_directory(builtin_skills_dir());
  for (const auto& dir : watched_skills_dirs()) {
    std::error_code ec;
    if (!std::filesystem::is_directory(dir, ec)) {
      // A directory asked for by name must exist (the error names it); the default
      // installed-skills directory need not.
      if (dir != options_.installed_skills_dir) registry_->load_directory(dir);
      continue;
    }
    recover_store(dir);
    for (const std::string& line : reloader_->sync(dir)) log(LogLevel::kInfo, "skills", line);
  }
  for (const std::string& conflict : registry_->conflicts()) {
    log(LogLevel::kWarning, "skills", "template conflict: " + conflict);
  }
}

std::vector<std::string> Host::reload_skills() {
  std::vector<std::string> changes;
  for (const auto& dir : watched_skills_dirs()) {
    for (std::string& line : reloader_->sync(dir)) {
      log(LogLevel::kInfo, "skills", line);
      console_.line("[" + line + "]");
      changes.push_back(std::move(line));
    }
  }
  return changes;
}

void Host::request_reload() {
  reload_requested_.store(true);
  loop_->wake();
}

void Host::watch_skills() {
  if (watcher_) return;
  watcher_ = std::make_unique<SkillWatcher>(watched_skills_dirs(), [this] { request_reload(); });
}

ConsoleReader::ConsoleReader(Host& host) {
  if (::pipe2(wake_, O_CLOEXEC) != 0) {
    throw std::runtime_error(std::string("cannot create a pipe: ") + std::strerror(errno));
  }
  thread_ = std::thread([this, &host] { read_lines(host); });
}

ConsoleReader::~ConsoleReader() {
  [[maybe_unused]] auto written = ::write(wake_[1], "x", 1);
  thread_.join();
  ::close(wake_[0]);
  ::close(wake_[1]);
}

void ConsoleReader::read_lines(Host& host) {
  std::string pending;
  auto post = [&host](std::string line) {
    while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.pop_back();
    if (!line.empty()) host.loop().post(std::move(line));
  };
  char buffer[4096];
  for (;;) {
    pollfd fds[2] = {{STDIN_FILENO, POLLIN, 0}, {wake_[0], POLLIN, 0}};
    if (::poll(fds, 2, -1) < 0) {
      if (errno == EINTR) continue;
      break;
    }
    if (fds[1].revents != 0) return;  // stopped: the loop is not ours to close any more
    if (fds[0].revents == 0) continue;
    const ssize_t got = ::read(STDIN_FILENO, buffer, sizeof buffer);
    if (got < 0 && errno == EINTR) continue;
    if (got <= 0) break;  // end of input (or an unreadable one)
    pending.append(buffer, static_cast<std::size_t>(got));
    for (std::size_t nl; (nl = pending.find('\n')) != std::string::npos;) {
      post(pending.substr(0, nl));
      pending.erase(0, nl + 1);
    }
  }
  post(std::move(pending));  // a last line without a newline, as std::getline has it
  host.loop().close();
}

}  // namespace marvin::app
