#include "store/semver.h"

#include <charconv>
#include <stdexcept>

namespace marvin::store {
namespace {

bool is_numeric(std::string_view s) {
  if (s.empty()) return false;
  for (char c : s) {
    if (c < '0' || c > '9') return false;
  }
  return true;
}

bool valid_identifiers(std::string_view s) {
  if (s.empty()) return false;
  std::size_t start = 0;
  while (true) {
    std::size_t dot = s.find('.', start);
    std::string_view id = s.substr(start, dot == std::string_view::npos ? dot : dot - start);
    if (id.empty()) return false;
    for (char c : id) {
      bool ok = (c >= '0' && c <= '9') || (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '-';
      if (!ok) return false;
    }
    if (dot == std::string_view::npos) return true;
    start = dot + 1;
  }
}

std::uint64_t parse_number(std::string_view s, bool& ok) {
  if (!is_numeric(s) || (s.size() > 1 && s[0] == '0') || s.size() > 18) {
    ok = false;
    return 0;
  }
  std::uint64_t v = 0;
  std::from_chars(s.data(), s.data() + s.size(), v);
  return v;
}

std::vector<std::string_view> split(std::string_view s, char sep) {
  std::vector<std::string_view> out;
  std::size_t start = 0;
  while (true) {
    std::size_t p = s.find(sep, start);
    out.push_back(s.substr(start, p == std::string_view::npos ? p : p - start));
    if (p == std::string_view::npos) return out;
    start = p + 1;
  }
}

int compare_prerelease(std::string_view a, std::string_view b) {
  if (a.empty() && b.empty()) return 0;
  if (a.empty()) return 1;  // a release outranks its pre-releases
  if (b.empty()) return -1;
  std::vector<std::string_view> x = split(a, '.'), y = split(b, '.');
  for (std::size_t i = 0; i < x.size() && i < y.size(); ++i) {
    bool xn = is_numeric(x[i]), yn = is_numeric(y[i]);
    if (xn && yn) {
      if (x[i].size() != y[i].size()) return x[i].size() < y[i].size() ? -1 : 1;
      int c = x[i].compare(y[i]);
      if (c != 0) return c < 0 ? -1 : 1;
    } else if (xn != yn) {
      return xn ? -1 : 1;
    } else {
      int c = x[i].compare(y[i]);
      if (c != 0) return c < 0 ? -1 : 1;
    }
  }
  if (x.size() == y.size()) return 0;
  return x.size() < y.size() ? -1 : 1;
}

}  // namespace

Version parse_version(std::string_view text, const std::string& field, bool allow_short) {
  auto bad = [&]() -> std::runtime_error {
    return std::runtime_error(field + ": \"" + std::string(text) + "\" is not a semantic version (MAJOR.MINOR.PATCH" +
                              (allow_short ? ", or MAJOR.MINOR" : "") + ")");
  };
  if (text.size() > 128) throw bad();
  Version v;
  v.text = std::string(text);
  std::string_view core = text;
  if (std::size_t plus = core.find('+'); plus != std::string_view::npos) {
    v.build = std::string(core.substr(plus + 1));
    core = core.substr(0, plus);
    if (!valid_identifiers(v.build)) throw bad();
  }
  if (std::size_t dash = core.find('-'); dash != std::string_view::npos) {
    v.prerelease = std::string(core.substr(dash + 1));
    core = core.substr(0, dash);
    if (!valid_identifiers(v.prerelease)) throw bad();
  }
  std::vector<std::string_view> parts = split(core, '.');
  if (parts.size() > 3 || (!allow_short && parts.size() != 3)) throw bad();
  bool ok = true;
  v.major = parse_number(parts[0], ok);
  if (parts.size() > 1) v.minor = parse_number(parts[1], ok);
  if (parts.size() > 2) v.patch = parse_number(parts[2], ok);
  if (!ok) throw bad();
  return v;
}

int compare_versions(const Version& a, const Version& b) {
  if (a.major != b.major) return a.major < b.major ? -1 : 1;
  if (a.minor != b.minor) return a.minor < b.minor ? -1 : 1;
  if (a.patch != b.patch) return a.patch < b.patch ? -1 : 1;
  return compare_prerelease(a.prerelease, b.prerelease);
}

VersionRange VersionRange::parse(std::string_view text, const std::string& field) {
  VersionRange r;
  r.text_ = std::string(text);
  std::string normalised(text);
  for (char& c : normalised) {
    if (c == ',') c = ' ';
  }
  std::string_view rest = normalised;
  while (!rest.empty()) {
    std::size_t start = rest.find_first_not_of(' ');
    if (start == std::string_view::npos) break;
    rest = rest.substr(start);
    std::size_t end = rest.find(' ');
    std::string_view term = rest.substr(0, end);
    rest = end == std::string_view::npos ? std::string_view{} : rest.substr(end);
    auto version = [&](std::string_view t) { return parse_version(t, field, /*allow_short=*/true); };
    if (term.rfind(">=", 0) == 0) {
      r.terms_.emplace_back(Op::kGe, version(term.substr(2)));
    } else if (term.rfind("<=", 0) == 0) {
      r.terms_.emplace_back(Op::kLe, version(term.substr(2)));
    } else if (term.rfind('>', 0) == 0) {
      r.terms_.emplace_back(Op::kGt, version(term.substr(1)));
    } else if (term.rfind('<', 0) == 0) {
      r.terms_.emplace_back(Op::kLt, version(term.substr(1)));
    } else if (term.rfind('=', 0) == 0) {
      r.terms_.emplace_back(Op::kEq, version(term.substr(1)));
    } else if (term.rfind('~', 0) == 0) {
      Version lo = version(term.substr(1));
      Version hi;
      hi.major = lo.major;
      hi.minor = lo.minor + 1;
      r.terms_.emplace_back(Op::kGe, lo);
      r.terms_.emplace_back(Op::kLt, hi);
    } else {
      Version lo = version(term.rfind('^', 0) == 0 ? term.substr(1) : term);
      Version hi;
      hi.major = lo.major + 1;
      r.terms_.emplace_back(Op::kGe, lo);
      r.terms_.emplace_back(Op::kLt, hi);
    }
  }
  if (r.terms_.empty()) throw std::runtime_error(field + ": empty version range");
  return r;
}

bool VersionRange::contains(const Version& v) const {
  for (const auto& [op, bound] : terms_) {
    int c = compare_versions(v, bound);
    bool ok = false;
    switch (op) {
      case Op::kGe: ok = c >= 0; break;
      case Op::kGt: ok = c > 0; break;
      case Op::kLe: ok = c <= 0; break;
      case Op::kLt: ok = c < 0; break;
      case Op::kEq: ok = c == 0; break;
    }
    if (!ok) return false;
  }
  return true;
}

}  // namespace marvin::store
