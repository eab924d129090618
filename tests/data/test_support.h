// Shared helpers of the data tests: a temporary directory holding the store's file, and the
// store's minute.
#pragma once

#include <cstdint>
#include <filesystem>

#include "support/files.h"

namespace marvin::data::test {

// One minute in the store's UTC milliseconds (the suites compile as one unity file, so they
// share this instead of each defining it).
inline constexpr std::int64_t kMinute = 60'000;

// A fresh temporary directory (tests/support), removed at scope exit, with the path the
// store's database file takes in it.
class TempDir : public marvin::test_support::TempDir {
 public:
  std::filesystem::path db() const { return path() / "marvin.db"; }
};

}  // namespace marvin::data::test
