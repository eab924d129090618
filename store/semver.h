// Semantic versions (skill versions, https://semver.org) and host API ranges.
#pragma once

#include <compare>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace marvin::store {

// MAJOR.MINOR.PATCH[-prerelease][+build]. Build metadata is kept for printing and ignored
// when comparing, as semver says.
struct Version {
  std::uint64_t major = 0, minor = 0, patch = 0;
  std::string prerelease;  // dot-separated identifiers, empty for a release
  std::string build;
  std::string text;        // as written
};

// Throws std::runtime_error naming `field` when `text` is not a semantic version. With
// `allow_short`, "1" and "1.2" are accepted (patch/minor 0): used for host API versions.
Version parse_version(std::string_view text, const std::string& field, bool allow_short = false);

// <0, 0, >0 with semver precedence.
int compare_versions(const Version& a, const Version& b);

// A host API range: comparators separated by spaces or commas, all of which must hold:
// ">=1.0", ">1.0", "<=1.2", "<2.0", "=1.0", "^1.2" (>=1.2, <2.0), "~1.2" (>=1.2, <1.3), or
// a bare "1.2" (same as ^1.2). Versions may be short ("1", "1.2").
class VersionRange {
 public:
  static VersionRange parse(std::string_view text, const std::string& field);
  bool contains(const Version& v) const;
  const std::string& text() const { return text_; }

 private:
  enum class Op { kGe, kGt, kLe, kLt, kEq };
  std::vector<std::pair<Op, Version>> terms_;
  std::string text_;
};

}  // namespace marvin::store
