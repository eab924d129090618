#include "sim/simulator.h"

#include <algorithm>
#include <cmath>

namespace marvin::sim {
namespace {

using navigation::Pose;
using navigation::Vec2;

constexpr double kEchoWindowS = 0.0145;        // 2 x 2.5 m / 346 m/s, rounded up: <= 69 readings/s
constexpr double kServoDegPerS = 60.0 / 0.14;  // MG996R

double rad(double deg) { return deg * navigation::kPi / 180.0; }

// Exact arc for constant wheel speeds over dt.
Pose drive(const Pose& p, double vl, double vr, double track, double dt) {
  const double v = (vl + vr) / 2, w = (vr - vl) / track;
  Pose n = p;
  if (std::fabs(w) < 1e-9) {
    n.x += v * dt * std::cos(p.heading);
    n.y += v * dt * std::sin(p.heading);
  } else {
    const double r = v / w, h2 = p.heading + w * dt;
    n.x += r * (std::sin(h2) - std::sin(p.heading));
    n.y -= r * (std::cos(h2) - std::cos(p.heading));
    n.heading = h2;
  }
  n.heading = navigation::wrap_angle(n.heading);
  return n;
}

}  // namespace

Simulator::Simulator(World world, SimOptions options)
    : world_(std::move(world)), options_(options), rng_(options.seed) {
  solids_ = world_.solid_segments();
  pose_ = odometry_ = world_.robot.start;
}

void Simulator::set_motor(int side, bool backward, std::uint8_t speed) {
  const double v = speed / 255.0 * world_.robot.max_speed_m_s;
  target_[side & 1] = backward ? -v : v;
}

void Simulator::set_head(int degrees) { head_target_deg_ = std::clamp(degrees, -60, 60); }
void Simulator::set_leds(std::uint8_t bits) { leds_ = bits; }

void Simulator::set_sweep(int mode, int from, int to, int step) {
  sweep_mode_ = mode;
  sweep_from_ = std::clamp(from, -45, 120);
  sweep_to_ = std::clamp(to, sweep_from_, 120);
  sweep_step_ = std::clamp(step, 1, 60);
  sweep_dir_ = 1;
  servo_target_ = sweep_from_;
  const double settle = std::ceil(std::fabs(servo_deg_ - servo_target_) * 140.0 / 60.0) / 1000.0;
  next_ping_s_ = time_s_ + settle + kEchoWindowS;
}

double Simulator::clearance_m(const Pose& pose) const {
  double best = 1e18;
  const Vec2 p = pose.position();
  for (const auto& s : solids_)
    best = std::min(best, navigation::point_segment_distance(p, s.a, s.b));
  return best;
}

double Simulator::sonar_geometry_m(const Pose& pose, double angle_deg) const {
  // Past 90 degrees the sweep points up and backwards.
  double heading = pose.heading, elevation = angle_deg;
  if (angle_deg > 90) {
    heading += navigation::kPi;
    elevation = 180 - angle_deg;
  }
  const double h = world_.robot.sonar_height_m, up = world_.wall_height_m - h;
  double best = std::numeric_limits<double>::infinity();
  if (elevation > 0.01) best = up / std::sin(rad(elevation));  // the ceiling
  if (elevation < 89.99) {
    const double tan_e = std::tan(rad(elevation)), cos_e = std::cos(rad(elevation));
    const int n = std::max(1, options_.cone_rays);
    const Vec2 o = pose.position();
    for (int k = 0; k < n; ++k) {
      const double off = n == 1 ? 0 : (k / (n - 1.0) - 0.5) * rad(options_.cone_deg);
      const Vec2 d{std::cos(heading + off), std::sin(heading + off)};
      // Looking down: the floor, or in a step down its lower floor (or its far side).
      double ray_best = best;
      if (elevation < -0.01) {
        double r = h / -tan_e;  // horizontal distance to the floor
        for (const Drop& drop : world_.drops) {
          if (!drop.box.contains(o + d * r)) continue;
          r = (h + drop.depth_m) / -tan_e;
          // Leaving the step's box before reaching its floor: its far side.
          for (int axis = 0; axis < 2; ++axis) {
            const double dv = axis == 0 ? d.x : d.y, ov = axis == 0 ? o.x : o.y;
            if (std::fabs(dv) < 1e-12) continue;
            const double bound = dv > 0 ? (axis == 0 ? drop.box.max.x : drop.box.max.y)
                                        : (axis == 0 ? drop.box.min.x : drop.box.min.y);
            r = std::min(r, (bound - ov) / dv);
          }
          break;
        }
        ray_best = std::min(ray_best, r / cos_e);
      }
      for (const auto& s : solids_) {
        const double r = navigation::ray_segment(o, d, s.a, s.b);
        if (r / cos_e >= ray_best) continue;
        if (h + r * tan_e > s.height) continue;  // passes over it
        ray_best = r / cos_e;
      }
      best = std::min(best, ray_best);  // the nearest echo of the cone comes back first
    }
  }
  return best;
}

SonarSample Simulator::measure(double angle_deg) {
  SonarSample s;
  s.angle_deg = static_cast<int>(std::lround(angle_deg));
  s.time_ms = time_ms();
  const double d = sonar_geometry_m(pose_, angle_deg);
  ++sonar_count_;
  const double noisy = d + gauss_(rng_) * (options_.sonar_noise_m + 0.01 * d);
  const bool lost = uniform_(rng_) < options_.sonar_dropout;
  if (!(noisy < kSonarMaxM) || lost) {
    s.distance_m = kSonarMaxM;
    s.echo = false;
  } else {
    s.distance_m = std::max(0.02, std::round(noisy * 1000.0) / 1000.0);  // mm, as on the wire
    s.echo = true;
  }
  return s;
}

void Simulator::step(double dt_s) {
  while (dt_s > 1e-12) {
    const double dt = std::min(dt_s, 0.05);
    step_base(dt);
    step_sonar(dt);
    // The head servo moves at the MG996R's speed toward its target.
    const double dh = head_target_deg_ - head_deg_, max = kServoDegPerS * dt;
    head_deg_ += std::clamp(dh, -max, max);
    time_s_ += dt;
    dt_s -= dt;
  }
}

void Simulator::step_base(double dt) {
  // Each side's speed follows its command within the acceleration limit.
  const double dv = world_.robot.accel_m_s2 * dt;
  for (int side = 0; side < 2; ++side) v_[side] += std::clamp(target_[side] - v_[side], -dv, dv);
  if (v_[0] == 0 && v_[1] == 0) return;
  const Pose next = drive(pose_, v_[0], v_[1], world_.robot.track_m, dt);
  const double now_clear = clearance_m(pose_), next_clear = clearance_m(next);
  if (next_clear < world_.robot.radius_m && next_clear < now_clear) {
    // The bumper: the body stops against the obstacle, the motors are cut.
    if (!touching_) {
      ++collisions_;
      if (on_collision_) on_collision_(pose_);
    }
    touching_ = true;
    v_[0] = v_[1] = target_[0] = target_[1] = 0;
    return;
  }
  touching_ = false;
  for (const Drop& drop : world_.drops) {
    if (drop.box.contains(next.position()) && !drop.box.contains(pose_.position())) {
      ++falls_;
      if (on_fall_) on_fall_(pose_, drop.name);
      v_[0] = v_[1] = target_[0] = target_[1] = 0;
      return;
    }
  }
  pose_ = next;
  // The encoders: each wheel's distance with a small random error.
  const double el = 1 + options_.odometry_noise * gauss_(rng_);
  const double er = 1 + options_.odometry_noise * gauss_(rng_);
  odometry_ = drive(odometry_, v_[0] * el, v_[1] * er, world_.robot.track_m, dt);
}

void Simulator::step_sonar(double dt) {
  // The servo moves toward its target at the MG996R's speed (for pictures); readings are
  // scheduled as the firmware does: settle ceil(|delta| * 140 / 60) ms, one echo window.
  const double ds = servo_target_ - servo_deg_, max = kServoDegPerS * dt;
  servo_deg_ += std::clamp(ds, -max, max);
  if (sweep_mode_ == 0) return;
  while (next_ping_s_ <= time_s_ + dt) {
    const double saved = time_s_;
    time_s_ = std::max(time_s_, next_ping_s_);
    SonarSample s = measure(servo_target_);
    time_s_ = saved;
    latest_[s.angle_deg] = s;
    int next = servo_target_;
    if (sweep_mode_ == 1 && sweep_to_ > sweep_from_) {
      next += sweep_dir_ * sweep_step_;
      if (next > sweep_to_ || next < sweep_from_) {
        sweep_dir_ = -sweep_dir_;
        next = servo_target_ + sweep_dir_ * sweep_step_;
      }
      next = std::clamp(next, sweep_from_, sweep_to_);
    }
    const double settle = std::ceil(std::abs(next - servo_target_) * 140.0 / 60.0) / 1000.0;
    next_ping_s_ += settle + kEchoWindowS;
    servo_target_ = next;
  }
}

}  // namespace marvin::sim
