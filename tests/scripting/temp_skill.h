// A fresh temporary directory (tests/support) to write a skill folder into (skill.json,
// main.lua, modules); removed with everything in it at scope exit.
#pragma once

#include <string>

#include "support/files.h"

namespace marvin::scripting::testing {

class TempDir : public marvin::test_support::TempDir {
 public:
  // Writes `text` to `relative` (folders are created).
  void write(const std::string& relative, const std::string& text) const {
    marvin::test_support::write_text(path() / relative, text);
  }
};

}  // namespace marvin::scripting::testing
