// `marvin devices list`: the smart-home devices the broker announces (Home Assistant
// discovery, Zigbee2MQTT), with rooms, state and the owner's aliases.
// `marvin devices alias add|remove|list`: the owner's names for devices ("the big lamp"),
// kept in the personal data store (SQLite) and applied by the host at start.
#include <filesystem>
#include <memory>
#include <string>

#include "app/cli.h"
#include "common/log.h"
#include "data/sqlite_store.h"
#include "home/config.h"
#include "home/discovery.h"
#include "home/home_service.h"

namespace marvin::app {
namespace {

struct DevicesOptions {
  std::string mqtt;
  std::string home_config;
  std::string data_dir;
  int wait_ms = 5000;
  std::string alias;
  std::string device;
};

std::filesystem::path store_path(const DevicesOptions& o) {
  return data::database_path(o.data_dir.empty() ? data::default_data_dir()
                                                : std::filesystem::path(o.data_dir));
}

home::HomeConfig config_of(const DevicesOptions& o) {
  try {
    if (!o.mqtt.empty()) {
      home::HomeConfig c;
      c.broker = home::broker_from_address(o.mqtt);
      return c;
    }
    std::optional<std::filesystem::path> path =
        o.home_config.empty() ? home::default_home_config_path()
                              : std::optional<std::filesystem::path>(o.home_config);
    if (!path || !std::filesystem::exists(*path)) {
      throw CliError(
          "no smart home configured: pass --mqtt HOST:PORT or --home-config FILE "
          "(or create " +
              (path ? path->string() : std::string("~/.config/marvin/home.json")) + ")",
          2);
    }
    return home::load_home_config(*path);
  } catch (const home::ConfigError& e) {
    throw CliError(e.what(), 2);
  }
}

void list_devices(const DevicesOptions& o) {
  set_log_level(LogLevel::kError);
  home::HomeConfig config = config_of(o);
  config.site += "-cli";  // its own client id and topics: never the running robot's
  home::HomeService service(config);
  std::error_code ec;
  if (std::filesystem::exists(store_path(o), ec)) {
    data::StoreOptions so;
    so.path = store_path(o);
    data::SqliteStore store(so);
    std::map<std::string, std::string> aliases;
    for (auto& [alias, device] : store.device_aliases()) aliases[alias] = device;
    service.set_aliases(std::move(aliases));
  }
  service.start();
  if (!service.settle(std::chrono::milliseconds(o.wait_ms))) {
    throw CliError("cannot reach the broker " + config.broker.host + ":" +
                       std::to_string(config.broker.port) + " within " + std::to_string(o.wait_ms) +
                       " ms",
                   1);
  }
  std::vector<home::Device> devices = service.devices();
  if (devices.empty())
    write_line("no devices announced on " + config.broker.host + ":" +
               std::to_string(config.broker.port));
  for (const home::Device& d : devices) {
    std::string state = !d.state.available ? "offline"
                        : !d.state.on      ? "state unknown"
                        : *d.state.on      ? "on"
                                           : "off";
    if (d.state.on == true && d.dimmable && d.state.brightness_pct)
      state += " " + std::to_string(*d.state.brightness_pct) + "%";
    if (d.type == home::DeviceType::kThermostat && d.state.target_c)
      state += ", set to " + home::celsius_text(*d.state.target_c) + " °C";
    if (d.type == home::DeviceType::kThermostat && d.state.current_c)
      state += ", measures " + home::celsius_text(*d.state.current_c) + " °C";
    std::string line = d.name + " (" + home::type_name(d.type) + (d.dimmable ? ", dimmable" : "") +
                       ") in " + (d.room.empty() ? std::string("no room") : d.room) + ": " + state +
                       " [" + d.id + "]";
    if (!d.aliases.empty()) {
      line += " aliases:";
      for (const std::string& a : d.aliases) line += " \"" + a + "\"";
    }
    write_line(line);
  }
  service.stop();
}

data::SqliteStore open_store(const DevicesOptions& o) {
  data::StoreOptions so;
  so.path = store_path(o);
  return data::SqliteStore(so);
}

void install_devices_commands(CLI::App& root) {
  auto o = std::make_shared<DevicesOptions>();
  CLI::App& devices = command_group(root, "devices", "Smart-home devices on the home's broker");
  CLI::App* list = devices.add_subcommand("list", "The devices the broker announces, with state");
  list->add_option("--mqtt", o->mqtt, "The broker HOST:PORT (no authentication)");
  list->add_option("--home-config", o->home_config,
                   "The smart-home config file (default: ~/.config/marvin/home.json)");
  list->add_option("--wait-ms", o->wait_ms, "How long to wait for the broker")
      ->check(CLI::Range(100, 60000));
  list->add_option("--data-dir", o->data_dir, "Personal data directory (aliases)");
  list->callback([o] { list_devices(*o); });

  CLI::App& alias = command_group(devices, "alias", "The owner's names for devices");
  CLI::App* add = alias.add_subcommand("add", "Call DEVICE (a name or id) also ALIAS");
  add->add_option("alias", o->alias, "e.g. \"the big lamp\"")->required();
  add->add_option("device", o->device, "e.g. \"living room lamp\"")->required();
  add->add_option("--data-dir", o->data_dir, "Personal data directory");
  add->callback([o] {
    data::SqliteStore store = open_store(*o);
    const std::string alias_text = home::lower(o->alias);
    try {
      store.set_device_alias(alias_text, home::lower(o->device));
    } catch (const std::invalid_argument& e) {
      throw CliError(e.what(), 2);
    }
    write_line("\"" + alias_text + "\" now means " + home::lower(o->device));
  });
  CLI::App* remove = alias.add_subcommand("remove", "Forget an alias");
  remove->add_option("alias", o->alias)->required();
  remove->add_option("--data-dir", o->data_dir, "Personal data directory");
  remove->callback([o] {
    data::SqliteStore store = open_store(*o);
    if (!store.remove_device_alias(home::lower(o->alias))) {
      throw CliError("there is no alias \"" + o->alias + "\"", 1);
    }
    write_line("forgot \"" + home::lower(o->alias) + "\"");
  });
  CLI::App* show = alias.add_subcommand("list", "The aliases");
  show->add_option("--data-dir", o->data_dir, "Personal data directory");
  show->callback([o] {
    data::SqliteStore store = open_store(*o);
    auto aliases = store.device_aliases();
    if (aliases.empty()) write_line("no aliases");
    for (auto& [a, d] : aliases) write_line("\"" + a + "\" -> " + d);
  });
}

}  // namespace

MARVIN_CLI_COMMANDS(install_devices_commands);

}  // namespace marvin::app
