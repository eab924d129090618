// marvin-mcu-sim for the device integration tests: started on a pseudo-terminal at `link`
// in the corridor room, writing its body's state to `state`, which the tests read back
// (mcu_state.h).
// Needs MARVIN_MCU_SIM and MARVIN_ROOM (tests/devices/CMakeLists.txt).
#pragma once

#include <filesystem>

#include "devices/mcu_state.h"
#include "support/child_process.h"

namespace marvin::devices::test {

// The simulator's stdout (the pty slave's name) goes to /dev/null; stderr is the test's.
inline test_support::ChildProcess start_mcu_simulator(const std::filesystem::path& link,
                                                      const std::filesystem::path& state) {
  test_support::ChildOptions options;
  options.in = test_support::ChildStream::kInherit;
  options.out = test_support::ChildStream::kNull;
  options.err = test_support::ChildStream::kInherit;
  return test_support::ChildProcess(
      {MARVIN_MCU_SIM, "--room", MARVIN_ROOM, "--link", link.string(), "--state", state.string()},
      options);
}

// The same in a world file (sim/world.h) instead of the corridor room.
inline test_support::ChildProcess start_mcu_simulator_in_world(const std::filesystem::path& world,
                                                               const std::filesystem::path& link,
                                                               const std::filesystem::path& state) {
  test_support::ChildOptions options;
  options.in = test_support::ChildStream::kInherit;
  options.out = test_support::ChildStream::kNull;
  options.err = test_support::ChildStream::kInherit;
  return test_support::ChildProcess({MARVIN_MCU_SIM, "--world", world.string(), "--link",
                                     link.string(), "--state", state.string()},
                                    options);
}

}  // namespace marvin::devices::test
