#include "store/package_manifest.h"

#include <algorithm>
#include <nlohmann/json.hpp>
#include <stdexcept>

namespace marvin::store {
namespace {

[[noreturn]] void fail(const std::string& origin, const std::string& field, const std::string& what) {
  throw std::runtime_error(origin + ": " + field + ": " + what);
}

const nlohmann::json& required(const nlohmann::json& j, const char* name, const std::string& origin) {
  auto it = j.find(name);
  if (it == j.end()) fail(origin, name, "missing (required)");
  return *it;
}

std::string required_string(const nlohmann::json& j, const char* name, const std::string& origin) {
  const nlohmann::json& v = required(j, name, origin);
  if (!v.is_string()) fail(origin, name, std::string("expected a string, found ") + v.type_name());
  return v.get<std::string>();
}

bool is_safe_file_name(std::string_view s) {
  if (s.empty() || s.size() > 255 || s == "." || s == "..") return false;
  for (char c : s) {
    if (c == '/' || c == '\\' || c == '\0') return false;
  }
  return true;
}

}  // namespace

bool is_valid_skill_id(std::string_view id) {
  if (id.empty() || id.size() > 64) return false;
  if (!((id[0] >= 'a' && id[0] <= 'z') || (id[0] >= '0' && id[0] <= '9'))) return false;
  for (char c : id) {
    bool ok = (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '.' || c == '_' || c == '-';
    if (!ok) return false;
  }
  return id.find("..") == std::string_view::npos;
}

PackageManifest parse_package_manifest(std::string_view json_text, const std::string& origin) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(json_text);
  } catch (const nlohmann::json::parse_error& e) {
    throw std::runtime_error(origin + ": not valid JSON: " + e.what());
  }
  if (!j.is_object()) throw std::runtime_error(origin + ": expected a JSON object at the top level");
  PackageManifest m{.id = {}, .version = {}, .kind = {},
                    .host_api = VersionRange::parse("0", "host_api"), .permissions = {}, .library = {}};
  m.id = required_string(j, "id", origin);
  if (!is_valid_skill_id(m.id)) {
    fail(origin, "id", "\"" + m.id + "\" is not a valid skill id (lower-case letters, digits, '.', '_', '-'; "
                       "starts with a letter or digit; at most 64 characters)");
  }
  std::string version = required_string(j, "version", origin);
  try {
    m.version = parse_version(version, "version");
  } catch (const std::exception& e) {
    throw std::runtime_error(origin + ": " + e.what());
  }
  m.kind = required_string(j, "kind", origin);
  if (m.kind != "native" && m.kind != "lua") {
    fail(origin, "kind", "\"" + m.kind + "\" is not \"native\" or \"lua\"");
  }
  // The host's manifest writes the range as {"min": "1.0", "max": "1.3"} (max optional: any
  // minor of min's major); older packages as a range string. Both mean the same here.
  std::string host_api;
  const nlohmann::json& api = required(j, "host_api", origin);
  if (api.is_object()) {
    auto min = api.find("min");
    if (min == api.end() || !min->is_string()) fail(origin, "host_api.min", "expected a string such as \"1.0\"");
    host_api = "^" + min->get<std::string>();
    if (auto max = api.find("max"); max != api.end()) {
      if (!max->is_string()) fail(origin, "host_api.max", "expected a string such as \"1.3\"");
      host_api = ">=" + min->get<std::string>() + " <=" + max->get<std::string>();
    }
  } else if (api.is_string()) {
    host_api = api.get<std::string>();
  } else {
    fail(origin, "host_api", std::string("expected an object {\"min\": ...} or a range string, found ") + api.type_name());
  }
  try {
    m.host_api = VersionRange::parse(host_api, "host_api");
  } catch (const std::exception& e) {
    throw std::runtime_error(origin + ": " + e.what());
  }
  if (auto it = j.find("permissions"); it != j.end()) {
    if (!it->is_array()) fail(origin, "permissions", std::string("expected an array of strings, found ") + it->type_name());
    for (std::size_t i = 0; i < it->size(); ++i) {
      const nlohmann::json& p = (*it)[i];
      if (!p.is_string() || p.get<std::string>().empty()) {
        fail(origin, "permissions[" + std::to_string(i) + "]", "expected a non-empty string");
      }
      m.permissions.push_back(p.get<std::string>());
    }
    std::sort(m.permissions.begin(), m.permissions.end());
    m.permissions.erase(std::unique(m.permissions.begin(), m.permissions.end()), m.permissions.end());
  }
  if (m.kind == "native") {
    const nlohmann::json* lib = nullptr;
    std::string field = "library";
    if (auto it = j.find("library"); it != j.end()) {
      lib = &*it;
    } else if (auto n = j.find("native"); n != j.end() && n->is_object() && n->contains("library")) {
      lib = &(*n)["library"];
      field = "native.library";
    }
    if (lib == nullptr) fail(origin, "library", "missing (required for a native skill: the .so file name)");
    if (!lib->is_string()) fail(origin, field, std::string("expected a string, found ") + lib->type_name());
    m.library = lib->get<std::string>();
    if (!is_safe_file_name(m.library)) {
      fail(origin, field, "\"" + m.library + "\" must be a plain file name inside the package");
    }
  }
  return m;
}

}  // namespace marvin::store
