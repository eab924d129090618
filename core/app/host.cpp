#include "app/host.h"

#include <date/tz.h>

#include "common/log.h"
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

std::filesystem::path builtin_skills_dir() { return MARVIN_BUILTIN_SKILLS_DIR; }

std::string system_time_zone() {
  try {
    return date::current_zone()->name();
  } catch (const std::exception&) {
    return "UTC";
  }
}

Host::Host(HostOptions options, std::function<void(std::string_view)> write_line)
    : options_(std::move(options)), console_(std::move(write_line)), body_(console_) {
  services_.data = &data_;
  services_.body = &body_;
  services_.time_zone = options_.time_zone.empty() ? system_time_zone() : options_.time_zone;
  if (options_.fixed_now_ms) {
    std::int64_t now = *options_.fixed_now_ms;
    services_.now_ms = [now] { return now; };
  } else {
    services_.now_ms = skills::system_now_ms;
  }
  loop_ = std::make_unique<skills::HostLoop>(
      [this](std::string_view text) { console_.line("Marvin: " + std::string(text)); });
  registry_ = std::make_unique<skills::Registry>(services_);
#ifdef MARVIN_HAVE_LUA
  registry_->add_runtime(std::make_unique<scripting::LuaRuntime>());
#endif
  manager_ = std::make_unique<skills::Manager>(*registry_, *loop_);
  services_.user = manager_.get();
  loop_->attach(*manager_, registry_->interpreter());
}

Host::~Host() {
  manager_.reset();   // joins a running task first
  registry_.reset();  // then the skills go
}

void Host::add_runtime(std::unique_ptr<skills::SkillRuntime> runtime) {
  registry_->add_runtime(std::move(runtime));
}

void Host::load() {
  if (options_.builtin_skills) registry_->load_directory(builtin_skills_dir());
  for (const auto& dir : options_.skills_dirs) registry_->load_directory(dir);
  for (const std::string& conflict : registry_->conflicts()) {
    log(LogLevel::kWarning, "skills", "template conflict: " + conflict);
  }
}

}  // namespace marvin::app
