// What a call says when no program can be found: runs `call` with PATH pointing nowhere and
// returns the message of the std::runtime_error it throws (empty when it throws none). PATH
// is put back however `call` ends, so one test cannot leave the next without programs.
#pragma once

#include <cstdlib>
#include <optional>
#include <stdexcept>
#include <string>

namespace marvin::perception::kws::testing {

template <typename Call>
std::string error_without_programs(Call call) {
  struct RestorePath {
    std::optional<std::string> saved;
    ~RestorePath() {
      if (saved)
        setenv("PATH", saved->c_str(), 1);
      else
        unsetenv("PATH");
    }
  } restore;
  if (const char* path = std::getenv("PATH")) restore.saved = path;
  setenv("PATH", "/nonexistent", 1);
  try {
    call();
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return {};
}

}  // namespace marvin::perception::kws::testing
