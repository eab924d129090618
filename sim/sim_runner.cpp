#include "sim/sim_runner.h"

#include "devices/motor_base.h"

namespace marvin::sim {
namespace {

constexpr double kStepS = 0.01;

std::int64_t steady_ms() {
  return std::chrono::duration_cast<std::chrono::milliseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

}  // namespace

SimRunner::SimRunner(World world, SimOptions options, double speed)
    : sim_(std::move(world), options), speed_(speed > 0 ? speed : 1) {}

SimRunner::~SimRunner() {
  {
    std::lock_guard lock(mu_);
    quit_ = true;
  }
  stepped_.notify_all();
  if (thread_.joinable()) thread_.join();
}

void SimRunner::start() {
  std::lock_guard lock(mu_);
  if (started_) return;
  started_ = true;
  thread_ = std::thread([this] { run(); });
}

void SimRunner::step_locked(double dt) {
  sim_.step(dt);
  if (move_until_ms_ >= 0 && sim_.time_ms() >= move_until_ms_) {
    sim_.set_motor(0, false, 0);
    sim_.set_motor(1, false, 0);
    move_until_ms_ = -1;
  }
}

void SimRunner::run() {
  // Paced: simulated time runs `speed_` times as fast as the wall clock.
  const auto start = std::chrono::steady_clock::now();
  std::int64_t steps = 0;
  std::unique_lock lock(mu_);
  while (!quit_) {
    step_locked(kStepS);
    ++steps;
    lock.unlock();
    stepped_.notify_all();
    const auto due = start + std::chrono::microseconds(static_cast<std::int64_t>(
                                 static_cast<double>(steps) * kStepS * 1e6 / speed_));
    lock.lock();
    stepped_.wait_until(lock, due, [&] { return quit_; });
  }
}

void SimRunner::advance(std::chrono::milliseconds ms) {
  std::lock_guard lock(mu_);
  const std::int64_t n = ms.count() / 10;
  for (std::int64_t i = 0; i < n; ++i) step_locked(kStepS);
}

bool SimRunner::wait(std::chrono::milliseconds ms, const std::function<bool()>& cancelled) {
  std::unique_lock lock(mu_);
  const std::int64_t until = sim_.time_ms() + ms.count();
  if (!started_) {
    while (sim_.time_ms() < until) {
      if (cancelled()) return true;
      step_locked(kStepS);
    }
    return cancelled();
  }
  stepped_.wait(lock, [&] { return quit_ || cancelled() || sim_.time_ms() >= until; });
  return cancelled();
}

void SimRunner::poke() {
  { std::lock_guard lock(mu_); }
  stepped_.notify_all();
}

void SimRunner::move(devices::Direction direction, std::uint8_t speed,
                     std::chrono::milliseconds duration) {
  // The two locomotion frames the serial body would send, decoded as the firmware does:
  // direction code 0 left forward, 1 left backward, 2 right forward, 3 right backward.
  const auto [left, right] = devices::MotorBase::wheel_codes(direction);
  std::lock_guard lock(mu_);
  for (std::uint8_t code : {left, right}) sim_.set_motor(code >> 1, (code & 1) != 0, speed);
  move_until_ms_ = speed == 0 ? -1 : sim_.time_ms() + duration.count();
}

void SimRunner::stop() {
  std::lock_guard lock(mu_);
  sim_.set_motor(0, false, 0);
  sim_.set_motor(1, false, 0);
  move_until_ms_ = -1;
}

void SimRunner::tilt_head(int degrees) {
  std::lock_guard lock(mu_);
  sim_.set_head(degrees);
}

void SimRunner::set_light(devices::Light light) {
  // The LEDS frame's bits: red awaiting, green listening, yellow executing.
  static const std::uint8_t bits[] = {0, 1, 2, 4};
  std::lock_guard lock(mu_);
  sim_.set_leds(bits[static_cast<int>(light)]);
}

std::vector<devices::ScanPoint> SimRunner::latest_scan() {
  std::lock_guard lock(mu_);
  const std::int64_t now_steady = steady_ms(), now_sim = sim_.time_ms();
  std::vector<devices::ScanPoint> out;
  for (const auto& [angle, s] : sim_.latest_sonar()) {
    const auto age = static_cast<std::int64_t>(static_cast<double>(now_sim - s.time_ms) / speed_);
    out.push_back({static_cast<double>(angle), s.distance_m, now_steady - age});
  }
  return out;
}

std::vector<devices::ScanPoint> SimRunner::sim_scan() const {
  std::lock_guard lock(mu_);
  std::vector<devices::ScanPoint> out;
  for (const auto& [angle, s] : sim_.latest_sonar())
    out.push_back({static_cast<double>(angle), s.distance_m, s.time_ms});
  return out;
}

navigation::Pose SimRunner::odometry() const {
  std::lock_guard lock(mu_);
  return sim_.odometry();
}
CameraView SimRunner::camera_view() const {
  std::lock_guard lock(mu_);
  return {sim_.pose(), sim_.head_deg(), sim_.time_ms() * 1000};
}

navigation::Pose SimRunner::true_pose() const {
  std::lock_guard lock(mu_);
  return sim_.pose();
}
std::int64_t SimRunner::now_ms() const {
  std::lock_guard lock(mu_);
  return sim_.time_ms();
}
void SimRunner::inspect(const std::function<void(const Simulator&)>& f) const {
  std::lock_guard lock(mu_);
  f(sim_);
}
void SimRunner::on_fall(std::function<void(const navigation::Pose&, const std::string&)> f) {
  std::lock_guard lock(mu_);
  sim_.on_fall(std::move(f));
}

void SimRunner::set_sweep(int mode, int from, int to, int step) {
  std::lock_guard lock(mu_);
  sim_.set_sweep(mode, from, to, step);
}

void SimRunner::on_collision(std::function<void(const navigation::Pose&)> f) {
  std::lock_guard lock(mu_);
  sim_.on_collision(std::move(f));
}

}  // namespace marvin::sim
