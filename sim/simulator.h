// The simulated robot in its world, stepped in simulated time: the base (differential
// drive from the firmware's per-side commands: direction bit + 8-bit speed), the head's
// tilt servo, the status LEDs, and the HC-SR04 sonar on its sweep servo. Deterministic:
// the same world, seed and command sequence give the same poses and readings.
//
// Not thread-safe: SimRunner (sim/sim_runner.h) owns one and serialises access.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "sim/world.h"

namespace marvin::sim {

// One sonar measurement as the firmware reports it.
struct SonarSample {
  int angle_deg = 0;         // sweep angle 0..120
  double distance_m = 2.5;   // slant distance; 2.5 when nothing echoed
  bool echo = false;         // false: nothing within 2.5 m (or the echo was lost)
  std::int64_t time_ms = 0;  // simulated time
};

struct SimOptions {
  std::uint64_t seed = 1;
  double odometry_noise = 0.01;  // relative, per wheel and step (a random walk)
  double sonar_noise_m = 0.01;   // plus 1% of the distance, standard deviation
  double sonar_dropout = 0.02;   // chance that a real echo is lost
  double cone_deg = 15;          // the HC-SR04's beam, full width
  int cone_rays = 5;
};

class Simulator {
 public:
  static constexpr double kSonarMaxM = 2.5;
  static constexpr double kSoundM_S = 346.0;

  explicit Simulator(World world, SimOptions options = {});

  // --- what the firmware's HAL does (firmware/core/marvin_core.h: mv_hal) -------------
  // side 0 = left, 1 = right; speed 0..255 of max_speed_m_s; 0 stops that side.
  void set_motor(int side, bool backward, std::uint8_t speed);
  void set_head(int degrees);  // target of the tilt servo, -60..60
  void set_leds(std::uint8_t bits);
  // Sonar sweep as SONAR_SWEEP sets it: mode 0 off, 1 sweep from..to by step (bouncing),
  // 2 fixed at from. Angles -45..120 (negative looks down; the firmware's servo range is
  // 0..120, the simulated one reaches down too). The firmware's default: 1, 0, 60, 15.
  void set_sweep(int mode, int from, int to, int step);

  // Advances the world by dt_s (at most 0.05 s; longer steps are split).
  void step(double dt_s);

  // --- state -------------------------------------------------------------------------
  const World& world() const { return world_; }
  std::int64_t time_ms() const { return static_cast<std::int64_t>(time_s_ * 1000.0); }
  double time_s() const { return time_s_; }
  const navigation::Pose& pose() const { return pose_; }          // the truth
  const navigation::Pose& odometry() const { return odometry_; }  // what the wheels tell
  double left_m_s() const { return v_[0]; }
  double right_m_s() const { return v_[1]; }
  double head_deg() const { return head_deg_; }
  double sonar_servo_deg() const { return servo_deg_; }
  std::uint8_t leds() const { return leds_; }
  long collisions() const { return collisions_; }
  // Times the robot's centre went over the edge of a step down (the world's "drops").
  long falls() const { return falls_; }
  bool touching() const { return touching_; }
  // Readings taken so far at each angle: the latest per angle.
  const std::map<int, SonarSample>& latest_sonar() const { return latest_; }
  std::uint64_t sonar_count() const { return sonar_count_; }
  // Called on each new collision with the pose where it happened.
  void on_collision(std::function<void(const navigation::Pose&)> f) {
    on_collision_ = std::move(f);
  }
  // Called on each fall with the pose at the edge and the step's name. The body stays at
  // the edge with its motors cut (so a test can go on; a real robot would be on its side).
  void on_fall(std::function<void(const navigation::Pose&, const std::string&)> f) {
    on_fall_ = std::move(f);
  }

  // Where the body is in the way of a solid side: distance from the centre to the nearest.
  double clearance_m(const navigation::Pose& pose) const;
  // The noiseless distance the sonar would measure from `pose` at sweep angle `angle_deg`
  // (a cone of cone_rays rays); +inf (or beyond 2.5) when nothing is in range.
  double sonar_geometry_m(const navigation::Pose& pose, double angle_deg) const;
  // One reading with noise and dropouts, as the firmware would report it.
  SonarSample measure(double angle_deg);

 private:
  void step_base(double dt);
  void step_sonar(double dt);

  World world_;
  SimOptions options_;
  std::vector<navigation::Segment> solids_;
  std::mt19937_64 rng_;
  std::normal_distribution<double> gauss_{0.0, 1.0};
  std::uniform_real_distribution<double> uniform_{0.0, 1.0};
  double time_s_ = 0;
  navigation::Pose pose_, odometry_;
  double target_[2] = {0, 0}, v_[2] = {0, 0};
  double head_deg_ = 0, head_target_deg_ = 0;
  std::uint8_t leds_ = 0;
  long collisions_ = 0, falls_ = 0;
  bool touching_ = false;
  std::function<void(const navigation::Pose&)> on_collision_;
  std::function<void(const navigation::Pose&, const std::string&)> on_fall_;
  // sonar
  int sweep_mode_ = 1, sweep_from_ = 0, sweep_to_ = 60, sweep_step_ = 15, sweep_dir_ = 1;
  double servo_deg_ = 0;
  int servo_target_ = 0;
  double next_ping_s_ = 0;
  std::map<int, SonarSample> latest_;
  std::uint64_t sonar_count_ = 0;
};

}  // namespace marvin::sim
