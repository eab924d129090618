// `marvin data export|import`, `marvin contacts add|list|remove`,
// `marvin schedule add|list|remove`, `marvin people list`: the carer's view of the
// personal data store. Every command takes --data-dir (default: default_data_dir()).
#include <date/tz.h>
#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <memory>
#include <optional>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "app/cli.h"
#include "data/recurrence.h"
#include "data/sqlite_store.h"

namespace marvin::app {
namespace {

using data::Recurrence;
using data::SqliteStore;

struct DataDirOption {
  std::string dir;
  void add_to(CLI::App& cmd) {
    cmd.add_option("--data-dir", dir,
                   "Directory holding marvin.db (default: $MARVIN_DATA_DIR, "
                   "$XDG_DATA_HOME/marvin, ~/.local/share/marvin)");
  }
  SqliteStore open() const {
    data::StoreOptions o;
    o.path = data::database_path(dir.empty() ? data::default_data_dir() : std::filesystem::path(dir));
    return SqliteStore(o);
  }
};

std::string join(const std::vector<std::string>& parts, const char* sep) {
  std::string out;
  for (const auto& p : parts) {
    if (!out.empty()) out += sep;
    out += p;
  }
  return out;
}

// The owner's zone: $TZ if it names a zone, else the system's, else UTC.
std::string local_zone() {
  if (const char* tz = std::getenv("TZ"); tz && *tz) {
    try {
      return std::string(date::locate_zone(*tz == ':' ? tz + 1 : tz)->name());
    } catch (const std::exception&) {
    }
  }
  try {
    return std::string(date::current_zone()->name());
  } catch (const std::exception&) {
    return "UTC";
  }
}

// The store's rule (data::parse_repeat), with the CLI's option names in its errors.
Recurrence parse_repeat(const std::string& repeat, const std::string& window) {
  try {
    return data::parse_repeat(repeat, window);
  } catch (const std::runtime_error& e) {
    throw CliError(std::string("--") + e.what(), 2);
  }
}

void print_reminder(const data::Reminder& r) {
  std::printf("%lld  %s  %-16s %s  (%s, by %s)\n", static_cast<long long>(r.id),
              data::format_local(r.next_fire_utc_ms, r.time_zone).c_str(),
              data::describe(r.recurrence).c_str(), r.title.c_str(), r.time_zone.c_str(),
              r.created_by.c_str());
}

// Writes `text` to `path` through a temporary file, fsync and rename: a crash leaves
// either the old file or the complete new one.
void write_file_atomically(const std::string& path, const std::string& text) {
  const std::string tmp = path + ".tmp";
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0600);
  if (fd < 0) throw CliError("cannot write " + tmp + ": " + std::strerror(errno));
  std::size_t done = 0;
  while (done < text.size()) {
    const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
    if (n < 0) {
      ::close(fd);
      throw CliError("cannot write " + tmp + ": " + std::strerror(errno));
    }
    done += static_cast<std::size_t>(n);
  }
  if (::fsync(fd) != 0 || ::close(fd) != 0)
    throw CliError("cannot write " + tmp + ": " + std::strerror(errno));
  if (std::rename(tmp.c_str(), path.c_str()) != 0)
    throw CliError("cannot rename " + tmp + " to " + path + ": " + std::strerror(errno));
}

void install_data(CLI::App& root) {
  // --- marvin data ------------------------------------------------------------------
  CLI::App& data_group = command_group(root, "data", "Back up and restore the personal data");
  {
    auto* cmd = data_group.add_subcommand("export", "Write all personal data to a JSON file");
    auto dir = std::make_shared<DataDirOption>();
    auto file = std::make_shared<std::string>();
    cmd->add_option("FILE", *file, "Backup file to write (JSON)")->required();
    dir->add_to(*cmd);
    cmd->callback([dir, file] {
      SqliteStore store = dir->open();
      const nlohmann::json doc = store.export_json();
      write_file_atomically(*file, doc.dump(2) + "\n");
      std::printf("exported %zu reminders, %zu contacts, %zu people, %zu sightings to %s\n",
                  doc["reminders"].size(), doc["contacts"].size(), doc["people"].size(),
                  doc["sightings"].size(), file->c_str());
    });
  }
  {
    auto* cmd = data_group.add_subcommand(
        "import", "Restore personal data from a JSON backup (replaces what is stored)");
    auto dir = std::make_shared<DataDirOption>();
    auto file = std::make_shared<std::string>();
    auto replace = std::make_shared<bool>(false);
    cmd->add_option("FILE", *file, "Backup file made by `marvin data export`")->required();
    cmd->add_flag("--replace", *replace, "Overwrite a database that already holds data");
    dir->add_to(*cmd);
    cmd->callback([dir, file, replace] {
      std::ifstream in(*file, std::ios::binary);
      if (!in) throw CliError("cannot read " + *file + ": " + std::strerror(errno));
      nlohmann::json doc;
      try {
        doc = nlohmann::json::parse(in);
      } catch (const nlohmann::json::parse_error& e) {
        throw CliError(*file + ": not valid JSON (" + e.what() + "); nothing was imported");
      }
      SqliteStore store = dir->open();
      if (!*replace && store.row_count() > 0)
        throw CliError("database " + store.path().string() +
                       " already holds data; pass --replace to overwrite it with " + *file +
                       " (export it first if unsure)");
      try {
        store.import_json(doc, *file);
      } catch (const std::exception& e) {
        throw CliError(std::string(e.what()) + "; nothing was imported");
      }
      const std::size_t sightings = doc.contains("sightings") ? doc["sightings"].size() : 0;
      std::printf("imported %zu reminders, %zu contacts, %zu people, %zu sightings from %s\n",
                  doc["reminders"].size(), doc["contacts"].size(), doc["people"].size(),
                  sightings, file->c_str());
    });
  }

  // --- marvin contacts ------------------------------------------------------------------
  CLI::App& contacts = command_group(root, "contacts", "The owner's contacts");
  {
    auto* cmd = contacts.add_subcommand("add", "Add a contact");
    auto dir = std::make_shared<DataDirOption>();
    auto c = std::make_shared<data::Contact>();
    cmd->add_option("NAME", c->name, "Full name, e.g. \"Anna Schmidt\"")->required();
    cmd->add_option("--phone", c->phone_numbers, "Phone number (repeatable)");
    cmd->add_option("--alias", c->aliases, "Another name, e.g. \"my daughter\" (repeatable)");
    cmd->add_option("--relation", c->relation, "e.g. daughter, doctor");
    cmd->add_option("--sip", c->sip_uris, "SIP address, e.g. sip:anna@example.org (repeatable)");
    cmd->add_option("--emergency", c->emergency_order,
                    "Order in which \"call for help\" tries this contact (1 = first)");
    dir->add_to(*cmd);
    cmd->callback([dir, c] {
      SqliteStore store = dir->open();
      std::printf("added contact %lld %s\n", static_cast<long long>(store.add_contact(*c)),
                  c->name.c_str());
    });
  }
  {
    // Each given option replaces that field (a repeatable one: the whole list); --clear-*
    // empties a list; --emergency 0 makes it no emergency contact. Checked before anything
    // is stored: a malformed field changes nothing.
    struct Edit {
      std::int64_t id = 0;
      std::optional<std::string> name, relation;
      std::optional<int> emergency;
      std::vector<std::string> phones, sips, aliases;
      bool clear_phones = false, clear_sips = false, clear_aliases = false;
    };
    auto* cmd = contacts.add_subcommand(
        "edit", "Change a contact: name, numbers, SIP addresses, relation, nicknames, emergency");
    auto dir = std::make_shared<DataDirOption>();
    auto e = std::make_shared<Edit>();
    cmd->add_option("ID", e->id, "Contact id (see `marvin contacts list`)")->required();
    cmd->add_option("--name", e->name, "New full name");
    auto* phone = cmd->add_option("--phone", e->phones, "Phone numbers (repeatable; replaces them)");
    auto* sip = cmd->add_option("--sip", e->sips, "SIP addresses (repeatable; replaces them)");
    auto* alias = cmd->add_option("--alias", e->aliases,
                                  "Nicknames, e.g. \"my daughter\" (repeatable; replaces them)");
    cmd->add_option("--relation", e->relation, "e.g. daughter, doctor (\"\" removes it)");
    cmd->add_option("--emergency", e->emergency,
                    "Order in which \"call for help\" tries this contact (0 = not at all)");
    cmd->add_flag("--clear-phone", e->clear_phones, "Remove every phone number")->excludes(phone);
    cmd->add_flag("--clear-sip", e->clear_sips, "Remove every SIP address")->excludes(sip);
    cmd->add_flag("--clear-alias", e->clear_aliases, "Remove every nickname")->excludes(alias);
    dir->add_to(*cmd);
    cmd->callback([dir, e] {
      SqliteStore store = dir->open();
      std::optional<data::Contact> found;
      for (data::Contact& c : store.list_contacts()) {
        if (c.id == e->id) found = std::move(c);
      }
      if (!found) throw CliError("no contact with id " + std::to_string(e->id));
      data::Contact c = *found;
      if (e->name) c.name = *e->name;
      if (e->relation) c.relation = *e->relation;
      if (e->emergency) c.emergency_order = *e->emergency;
      if (!e->phones.empty() || e->clear_phones) c.phone_numbers = e->phones;
      if (!e->sips.empty() || e->clear_sips) c.sip_uris = e->sips;
      if (!e->aliases.empty() || e->clear_aliases) c.aliases = e->aliases;
      try {
        if (!store.update_contact(c)) throw CliError("no contact with id " + std::to_string(e->id));
      } catch (const CliError&) {
        throw;
      } catch (const std::exception& error) {
        throw CliError("contacts edit " + std::to_string(e->id) + ": " + error.what() +
                           "; nothing was changed",
                       2);
      }
      std::printf("changed contact %lld %s\n", static_cast<long long>(c.id), c.name.c_str());
    });
  }
  {
    auto* cmd = contacts.add_subcommand("list", "List contacts");
    auto dir = std::make_shared<DataDirOption>();
    dir->add_to(*cmd);
    cmd->callback([dir] {
      SqliteStore store = dir->open();
      for (const data::Contact& c : store.list_contacts()) {
        std::printf("%lld  %s", static_cast<long long>(c.id), c.name.c_str());
        if (!c.relation.empty()) std::printf(" (%s)", c.relation.c_str());
        if (!c.phone_numbers.empty()) std::printf("  %s", join(c.phone_numbers, ", ").c_str());
        if (!c.sip_uris.empty()) std::printf("  %s", join(c.sip_uris, ", ").c_str());
        if (!c.aliases.empty()) std::printf("  aka %s", join(c.aliases, ", ").c_str());
        if (c.emergency_order > 0) std::printf("  emergency #%d", c.emergency_order);
        std::printf("\n");
      }
    });
  }
  {
    auto* cmd = contacts.add_subcommand("remove", "Remove a contact by id");
    auto dir = std::make_shared<DataDirOption>();
    auto id = std::make_shared<std::int64_t>(0);
    cmd->add_option("ID", *id, "Contact id (see `marvin contacts list`)")->required();
    dir->add_to(*cmd);
    cmd->callback([dir, id] {
      SqliteStore store = dir->open();
      if (!store.remove_contact(*id))
        throw CliError("no contact with id " + std::to_string(*id));
      std::printf("removed contact %lld\n", static_cast<long long>(*id));
    });
  }

  // --- marvin schedule ----------------------------------------------------------------
  CLI::App& schedule = command_group(root, "schedule", "Reminders and schedules");
  {
    auto* cmd = schedule.add_subcommand("add", "Add a reminder");
    auto dir = std::make_shared<DataDirOption>();
    struct Args {
      std::string title, at, tz, repeat = "once", window;
    };
    auto a = std::make_shared<Args>();
    cmd->add_option("TITLE", a->title, "What to remind of, e.g. \"take my pills\"")->required();
    cmd->add_option("--at", a->at, "First time, local: YYYY-MM-DDTHH:MM")->required();
    cmd->add_option("--tz", a->tz, "IANA time zone (default: $TZ or the system's)");
    cmd->add_option("--repeat", a->repeat,
                    "once | daily | weekdays | weekly:mon,thu | every:MINUTES (default once)");
    cmd->add_option("--window", a->window, "With every:MINUTES: HH:MM-HH:MM (end exclusive)");
    dir->add_to(*cmd);
    cmd->callback([dir, a] {
      data::Reminder r;
      r.title = a->title;
      r.time_zone = a->tz.empty() ? local_zone() : a->tz;
      r.recurrence = parse_repeat(a->repeat, a->window);
      r.created_by = "user";
      try {
        r.first_fire_utc_ms = data::local_to_utc_ms(a->at, r.time_zone);
      } catch (const std::exception& e) {
        throw CliError(std::string("--at: ") + e.what(), 2);
      }
      SqliteStore store = dir->open();
      const auto id = store.add_reminder(r);
      print_reminder(*store.get_reminder(id));
    });
  }
  {
    auto* cmd = schedule.add_subcommand("list", "List active reminders, soonest first");
    auto dir = std::make_shared<DataDirOption>();
    dir->add_to(*cmd);
    cmd->callback([dir] {
      SqliteStore store = dir->open();
      for (const data::Reminder& r : store.list_reminders()) print_reminder(r);
    });
  }
  {
    auto* cmd = schedule.add_subcommand("remove", "Cancel a reminder by id");
    auto dir = std::make_shared<DataDirOption>();
    auto id = std::make_shared<std::int64_t>(0);
    cmd->add_option("ID", *id, "Reminder id (see `marvin schedule list`)")->required();
    dir->add_to(*cmd);
    cmd->callback([dir, id] {
      SqliteStore store = dir->open();
      if (!store.remove_reminder(*id))
        throw CliError("no active reminder with id " + std::to_string(*id));
      std::printf("cancelled reminder %lld\n", static_cast<long long>(*id));
    });
  }

  // --- marvin people ------------------------------------------------------------------
  CLI::App& people = command_group(root, "people", "The people Marvin knows by face");
  {
    auto* cmd = people.add_subcommand("list", "List people and their face embeddings");
    auto dir = std::make_shared<DataDirOption>();
    dir->add_to(*cmd);
    cmd->callback([dir] {
      SqliteStore store = dir->open();
      // Who added faces and when: the face gallery logs each enrolment (core/vision).
      const auto events = store.recent_events(10000);
      for (const data::Person& p : store.list_people()) {
        std::printf("%lld  %s", static_cast<long long>(p.id), p.name.c_str());
        if (p.contact_id) std::printf("  contact %lld", static_cast<long long>(*p.contact_id));
        const auto faces = store.face_embeddings(p.id);
        std::printf("  %zu face embedding%s", faces.size(), faces.size() == 1 ? "" : "s");
        if (!faces.empty())
          std::printf(" (%s, %zu)", faces.front().model_id.c_str(), faces.front().values.size());
        for (const auto& e : events) {
          if (e.kind == "face_enrolled" && e.message.rfind(p.name + ": ", 0) == 0) {
            const auto t = std::chrono::sys_time<std::chrono::milliseconds>(
                std::chrono::milliseconds(e.time_utc_ms));
            std::printf("  last added by %s at %s UTC", e.source.c_str(),
                        date::format("%Y-%m-%d %H:%M", t).c_str());
            break;
          }
        }
        std::printf("\n");
      }
    });
  }
}

}  // namespace

MARVIN_CLI_COMMANDS(install_data);

}  // namespace marvin::app
