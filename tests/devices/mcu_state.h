// The state file marvin-mcu-sim --state writes every 100 ms, read back by the device tests
// and bench_serial_stall.
#pragma once

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

namespace marvin::devices::test {

// The simulator's last state, or null while there is none (not written yet, or caught
// mid-write: read again).
inline nlohmann::json read_state(const std::filesystem::path& p) {
  std::ifstream in(p);
  if (!in) return {};
  try {
    return nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception&) {
    return {};
  }
}

// Both sides' wheel speeds added up, whatever their direction: 0 when the wheels stand still.
inline int wheel_speeds(const nlohmann::json& state) {
  return std::abs(state.value("left", 0)) + std::abs(state.value("right", 0));
}

// How far the body has turned since it faced `from_deg`: degrees, -180..180, either way.
inline double turned_deg(const nlohmann::json& state, double from_deg) {
  return std::remainder(state.value("heading_deg", 0.0) - from_deg, 360.0);
}

}  // namespace marvin::devices::test
