// The simulated robot as the host uses it: a Simulator stepped on its own thread, `speed`
// times faster than real time, behind the devices::Body interface (the same commands the
// serial body sends: MotorBase::wheel_codes per side, timed moves, head, lights), and the
// pose, sonar and clock the navigator needs, all in simulated time.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <functional>
#include <mutex>
#include <thread>

#include "devices/body.h"
#include "navigation/navigator.h"
#include "sim/camera.h"
#include "sim/simulator.h"

namespace marvin::sim {

class SimRunner : public devices::Body {
 public:
  // `speed`: simulated seconds per wall-clock second (1 = real time).
  SimRunner(World world, SimOptions options, double speed);
  ~SimRunner() override;  // stops the thread
  SimRunner(const SimRunner&) = delete;
  SimRunner& operator=(const SimRunner&) = delete;

  // Starts stepping on a thread (10 ms steps). Without start(), advance() steps by hand.
  void start();
  // Steps `ms` of simulated time now, on the caller's thread (tests, benchmarks).
  void advance(std::chrono::milliseconds ms);

  // devices::Body. Durations are simulated time.
  void move(devices::Direction direction, std::uint8_t speed,
            std::chrono::milliseconds duration) override;
  void stop() override;
  void tilt_head(int degrees) override;
  // Latest reading per angle; time_ms on the steady clock, as the serial body stamps them.
  std::vector<devices::ScanPoint> latest_scan() override;
  void set_light(devices::Light light) override;

  // For the navigator: odometry pose, sonar stamped in simulated ms, simulated now.
  navigation::Pose odometry() const;
  navigation::Pose true_pose() const;
  std::vector<devices::ScanPoint> sim_scan() const;
  std::int64_t now_ms() const;
  // Waits until `ms` of simulated time passed (started runner) or steps it (not
  // started); returns true at once when `cancelled()` turns true (checked on each step).
  bool wait(std::chrono::milliseconds ms, const std::function<bool()>& cancelled);
  double speed() const { return speed_; }
  // The world (it does not change while the simulation runs).
  const World& world() const { return sim_.world(); }
  // What the robot's head camera sees now: true pose and head tilt, simulated time.
  CameraView camera_view() const;
  // The world's floor plan (what navigation is given).
  const navigation::FloorMap& floor_map() const { return sim_.world().map; }

  // Runs `f` with the simulator locked (pictures, tests).
  void inspect(const std::function<void(const Simulator&)>& f) const;
  void on_collision(std::function<void(const navigation::Pose&)> f);
  void on_fall(std::function<void(const navigation::Pose&, const std::string&)> f);
  // The sonar's sweep (Simulator::set_sweep: mode, from, to, step; angles -45..120).
  void set_sweep(int mode, int from, int to, int step);
  // Wakes every wait() so it re-checks its cancelled() (call after cancelling).
  void poke();

 private:
  void run();
  void step_locked(double dt);

  Simulator sim_;
  const double speed_;
  mutable std::mutex mu_;
  std::condition_variable stepped_;
  std::int64_t move_until_ms_ = -1;  // simulated time a timed move ends; -1: none
  bool started_ = false, quit_ = false;
  std::thread thread_;
};

}  // namespace marvin::sim
