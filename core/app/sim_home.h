// `marvin run --sim` in the simulated home: the world file's robot (sim::SimRunner, faster
// than real time with --speed), the navigator the skills go places with, collisions shown
// on the console, and with --show a floor-plan picture kept up to date.
#pragma once

#include <atomic>
#include <condition_variable>
#include <filesystem>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <string_view>
#include <thread>

#include "devices/serial_body.h"
#include "navigation/dead_reckoning.h"
#include "navigation/navigator.h"
#include "sim/sim_runner.h"

namespace marvin::app {

struct SimHomeOptions {
  std::filesystem::path world_file;  // required
  double speed = 1;                  // simulated seconds per second
  std::uint64_t seed = 1;
  std::filesystem::path show;  // a PNG to keep up to date; empty: none
};

class SimHome {
 public:
  // Loads the world (throws sim::WorldError naming the file and element) and starts the
  // simulation. `console` shows events such as collisions.
  SimHome(const SimHomeOptions& options, std::function<void(std::string_view)> console);
  ~SimHome();  // stops the picture and the simulation
  SimHome(const SimHome&) = delete;
  SimHome& operator=(const SimHome&) = delete;

  sim::SimRunner& body() { return *runner_; }
  navigation::Navigator& navigator() { return *navigator_; }
  // The robot's head camera in the simulated home (a vision::Camera for the vision graph):
  // each read() renders the robot's current view. Throws vision::CameraError when a photo
  // of the world cannot be read.
  std::unique_ptr<vision::Camera> camera();
  // Draws the picture now (also done every 500 ms with --show).
  void draw();

 private:
  SimHomeOptions options_;
  std::unique_ptr<sim::SimRunner> runner_;
  std::unique_ptr<navigation::Navigator> navigator_;
  std::mutex mu_;
  std::condition_variable wake_;
  bool quit_ = false;
  std::thread painter_;
};

// Going places on the base behind the serial link (the real robot, or marvin-mcu-sim --world):
// the world file's floor plan and the robot's start pose, the pose by dead reckoning of the
// commands sent (navigation/dead_reckoning.h), the sonar from the base.
class SerialNavigation {
 public:
  // Loads the world (throws sim::WorldError). `serial` must outlive this.
  SerialNavigation(const std::filesystem::path& world_file, devices::SerialBody& serial);
  ~SerialNavigation();
  navigation::Navigator& navigator() { return *navigator_; }

 private:
  std::unique_ptr<navigation::DeadReckoning> reckoning_;
  std::unique_ptr<navigation::Navigator> navigator_;
};

}  // namespace marvin::app
