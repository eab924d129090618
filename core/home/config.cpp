#include "home/config.h"

#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

namespace marvin::home {
namespace {

using nlohmann::json;

std::string octal(unsigned mode) {
  char text[8];
  std::snprintf(text, sizeof text, "%04o", mode & 07777u);
  return text;
}

template <class T>
T get(const json& object, const std::string& file, const std::string& path, const char* key,
      json::value_t type, const char* expected, T fallback) {
  auto it = object.find(key);
  if (it == object.end() || it->is_null()) return fallback;
  bool ok = it->type() == type ||
            (type == json::value_t::number_integer && it->is_number_unsigned());
  if (!ok) {
    throw ConfigError(file + ": " + path + "." + key + " must be " + expected + ", got " +
                      it->dump());
  }
  return it->get<T>();
}

}  // namespace

std::string read_password_file(const std::filesystem::path& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) {
    throw ConfigError("mqtt password file " + path.string() + " cannot be read (does it exist?)");
  }
  if (!S_ISREG(st.st_mode)) {
    throw ConfigError("mqtt password file " + path.string() + " is not a regular file");
  }
  if (st.st_uid != ::geteuid()) {
    throw ConfigError("mqtt password file " + path.string() + " belongs to user id " +
                      std::to_string(st.st_uid) + ", not to this user (" +
                      std::to_string(::geteuid()) + ")");
  }
  if ((st.st_mode & 077) != 0) {
    throw ConfigError("mqtt password file " + path.string() + " has mode " +
                      octal(st.st_mode) +
                      ": other users may read it; it must be readable by its owner only "
                      "(chmod 600 " + path.string() + ")");
  }
  std::ifstream in(path);
  std::string password;
  std::getline(in, password);
  if (!in && !in.eof()) throw ConfigError("cannot read mqtt password file " + path.string());
  while (!password.empty() && (password.back() == '\r' || password.back() == '\n'))
    password.pop_back();
  if (password.empty()) throw ConfigError("mqtt password file " + path.string() + " is empty");
  return password;
}

HomeConfig load_home_config(const std::filesystem::path& path) {
  const std::string file = path.string();
  std::ifstream in(path);
  if (!in) throw ConfigError("cannot read the home config " + file);
  std::stringstream text;
  text << in.rdbuf();
  json doc;
  try {
    doc = json::parse(text.str());
  } catch (const json::parse_error& e) {
    throw ConfigError(file + ": not valid JSON at byte " + std::to_string(e.byte));
  }
  if (!doc.is_object()) throw ConfigError(file + ": $ must be a JSON object");
  using V = json::value_t;
  HomeConfig c;
  if (auto it = doc.find("broker"); it != doc.end()) {
    if (!it->is_object()) throw ConfigError(file + ": $.broker must be an object");
    const json& b = *it;
    MqttOptions& o = c.broker;
    o.host = get<std::string>(b, file, "$.broker", "host", V::string, "a string", o.host);
    o.port = get<int>(b, file, "$.broker", "port", V::number_integer, "an integer", o.port);
    if (o.port <= 0 || o.port > 65535)
      throw ConfigError(file + ": $.broker.port must be 1..65535, got " + std::to_string(o.port));
    o.tls = get<bool>(b, file, "$.broker", "tls", V::boolean, "true or false", o.tls);
    o.ca_file = get<std::string>(b, file, "$.broker", "ca_file", V::string, "a string", "");
    o.user = get<std::string>(b, file, "$.broker", "user", V::string, "a string", "");
    std::string password_file =
        get<std::string>(b, file, "$.broker", "password_file", V::string, "a string", "");
    if (b.contains("password")) {
      throw ConfigError(file + ": $.broker.password is not read from the config file; put the "
                               "password in a file readable only by you and name it in "
                               "$.broker.password_file");
    }
    if (!password_file.empty()) {
      std::filesystem::path pf(password_file);
      if (pf.is_relative()) pf = path.parent_path() / pf;
      o.password = read_password_file(pf);
      if (o.user.empty()) throw ConfigError(file + ": $.broker.password_file needs $.broker.user");
    }
  }
  c.site = get<std::string>(doc, file, "$", "site", V::string, "a string", c.site);
  if (c.site.empty() || c.site.find_first_of("/#+") != std::string::npos) {
    throw ConfigError(file + ": $.site must be a non-empty topic level without / # +, got \"" +
                      c.site + "\"");
  }
  c.room = get<std::string>(doc, file, "$", "room", V::string, "a string", c.room);
  c.discovery_prefix = get<std::string>(doc, file, "$", "discovery_prefix", V::string,
                                        "a string", c.discovery_prefix);
  c.zigbee2mqtt_base = get<std::string>(doc, file, "$", "zigbee2mqtt_base", V::string,
                                        "a string", c.zigbee2mqtt_base);
  c.commands = get<bool>(doc, file, "$", "commands", V::boolean, "true or false", c.commands);
  int timeout = get<int>(doc, file, "$", "answer_timeout_ms", V::number_integer, "an integer",
                         static_cast<int>(c.answer_timeout.count()));
  if (timeout < 100 || timeout > 60000) {
    throw ConfigError(file + ": $.answer_timeout_ms must be 100..60000, got " +
                      std::to_string(timeout));
  }
  c.answer_timeout = std::chrono::milliseconds(timeout);
  return c;
}

std::optional<std::filesystem::path> default_home_config_path() {
  if (const char* env = std::getenv("MARVIN_HOME_CONFIG"); env && *env) return env;
  if (const char* xdg = std::getenv("XDG_CONFIG_HOME"); xdg && *xdg)
    return std::filesystem::path(xdg) / "marvin" / "home.json";
  if (const char* home = std::getenv("HOME"); home && *home)
    return std::filesystem::path(home) / ".config" / "marvin" / "home.json";
  return std::nullopt;
}

MqttOptions broker_from_address(const std::string& address) {
  MqttOptions o;
  std::size_t colon = address.rfind(':');
  o.host = address.substr(0, colon);
  if (colon != std::string::npos) {
    const std::string port = address.substr(colon + 1);
    char* end = nullptr;
    long value = std::strtol(port.c_str(), &end, 10);
    if (port.empty() || *end != '\0' || value <= 0 || value > 65535) {
      throw ConfigError("broker address \"" + address + "\": expected HOST:PORT with a port "
                        "1..65535");
    }
    o.port = static_cast<int>(value);
  }
  if (o.host.empty()) throw ConfigError("broker address \"" + address + "\" has no host");
  return o;
}

}  // namespace marvin::home
