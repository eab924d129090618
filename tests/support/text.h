// Text checks the suites share (error messages, output, generated grammars). Header-only:
// suites of one area compile as one unity file, so a copy in each file's anonymous
// namespace would be defined twice.
#pragma once

#include <string_view>

namespace marvin::test_support {

// Whether `part` occurs anywhere in `text`.
inline bool contains(std::string_view text, std::string_view part) {
  return text.find(part) != std::string_view::npos;
}

}  // namespace marvin::test_support
