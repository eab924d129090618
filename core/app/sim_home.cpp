#include "app/sim_home.h"

#include <cstdio>

#include "common/log.h"
#include "sim/render.h"

namespace marvin::app {

SimHome::SimHome(const SimHomeOptions& options, std::function<void(std::string_view)> console)
    : options_(options) {
  sim::World world = sim::load_world(options.world_file);
  sim::SimOptions sim_options;
  sim_options.seed = options.seed;
  runner_ = std::make_unique<sim::SimRunner>(std::move(world), sim_options, options.speed);
  runner_->on_collision([console](const navigation::Pose& p) {
    char text[96];
    std::snprintf(text, sizeof text, "[collision at (%.2f, %.2f)]", p.x, p.y);
    console(text);
  });
  runner_->on_fall([console](const navigation::Pose& p, const std::string& step) {
    char text[160];
    std::snprintf(text, sizeof text, "[fell down %s at (%.2f, %.2f)]", step.c_str(), p.x, p.y);
    console(text);
  });
  // The simulated sonar also looks down (30 degrees), so a step down is found: the
  // navigator tells it from the floor (navigation/sonar_sweep.h).
  runner_->set_sweep(1, -30, 60, 15);
  navigation::NavigatorOptions nav;
  nav.time_scale = runner_->speed();
  nav.sonar_height_m = runner_->world().robot.sonar_height_m;
  navigator_ = std::make_unique<navigation::Navigator>(
      runner_->floor_map(), *runner_, [r = runner_.get()] { return r->odometry(); },
      [r = runner_.get()] { return r->sim_scan(); }, [r = runner_.get()] { return r->now_ms(); },
      nav);
  runner_->start();
  if (!options_.show.empty()) {
    draw();
    painter_ = std::thread([this] {
      std::unique_lock lock(mu_);
      while (!wake_.wait_for(lock, std::chrono::milliseconds(500), [this] { return quit_; })) {
        lock.unlock();
        draw();
        lock.lock();
      }
    });
  }
}

SimHome::~SimHome() {
  {
    std::lock_guard lock(mu_);
    quit_ = true;
  }
  wake_.notify_all();
  if (painter_.joinable()) painter_.join();
  if (!options_.show.empty()) draw();
  navigator_->stop();
}

std::unique_ptr<vision::Camera> SimHome::camera() {
  sim::SimRunner* runner = runner_.get();
  return std::make_unique<sim::SimCamera>(runner->world(),
                                          [runner] { return runner->camera_view(); });
}

void SimHome::draw() {
  if (options_.show.empty()) return;
  std::vector<navigation::Vec2> path = navigator_->path();
  cv::Mat image;
  runner_->inspect([&](const sim::Simulator& s) {
    image = sim::render_map(s.world(), sim::robot_view(s, path));
  });
  try {
    sim::write_png(image, options_.show);
  } catch (const std::exception& e) {
    log(LogLevel::kWarning, "sim", e.what());
  }
}

SerialNavigation::SerialNavigation(const std::filesystem::path& world_file,
                                   devices::SerialBody& serial) {
  sim::World world = sim::load_world(world_file);
  navigation::BaseSpec base{world.robot.max_speed_m_s, world.robot.track_m, world.robot.accel_m_s2};
  reckoning_ =
      std::make_unique<navigation::DeadReckoning>(serial, serial.motors(), base, world.robot.start);
  navigator_ = std::make_unique<navigation::Navigator>(
      world.map, *reckoning_, [r = reckoning_.get()] { return r->pose(); },
      [&serial] { return serial.latest_scan(); },
      [] {
        return std::chrono::duration_cast<std::chrono::milliseconds>(
                   std::chrono::steady_clock::now().time_since_epoch())
            .count();
      });
}

SerialNavigation::~SerialNavigation() { navigator_->stop(); }

}  // namespace marvin::app
