#include "web/api.h"

#include <sodium.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <fstream>
#include <stdexcept>

#include "data/recurrence.h"
#include "data/sqlite_store.h"
#include "store/installer.h"
#include "web/live.h"

namespace marvin::web {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

std::string text_field(const json& doc, const char* name, bool required,
                       const std::string& fallback = "") {
  auto it = doc.find(name);
  if (it == doc.end() || it->is_null()) {
    if (required) throw ApiError(400, std::string("field '") + name + "': missing");
    return fallback;
  }
  if (!it->is_string()) throw ApiError(400, std::string("field '") + name + "': expected a string");
  std::string value = it->get<std::string>();
  if (required && value.empty()) throw ApiError(400, std::string("field '") + name + "': empty");
  return value;
}

std::vector<std::string> list_field(const json& doc, const char* name) {
  std::vector<std::string> out;
  auto it = doc.find(name);
  if (it == doc.end() || it->is_null()) return out;
  if (!it->is_array())
    throw ApiError(400, std::string("field '") + name + "': expected a list of strings");
  for (const json& v : *it) {
    if (!v.is_string())
      throw ApiError(400, std::string("field '") + name + "': expected a list of strings");
    if (!v.get<std::string>().empty()) out.push_back(v.get<std::string>());
  }
  return out;
}

json reminder_json(const data::Reminder& r) {
  const auto [repeat_spec, window] = data::format_repeat(r.recurrence);
  return {{"id", r.id},
          {"title", r.title},
          {"next", data::format_local(r.next_fire_utc_ms, r.time_zone)},
          {"next_utc_ms", r.next_fire_utc_ms},
          {"repeat", data::describe(r.recurrence)},
          {"repeat_spec", repeat_spec},  // as the form and `marvin schedule add --repeat` write it
          {"window", window},
          {"time_zone", r.time_zone},
          {"created_by", r.created_by}};
}

json contact_json(const data::Contact& c) {
  return {{"id", c.id},
          {"name", c.name},
          {"relation", c.relation},
          {"phones", c.phone_numbers},
          {"sip", c.sip_uris},
          {"aliases", c.aliases},
          {"emergency", c.emergency_order}};
}

json skill_json(const store::InstalledSkill& s) {
  json j = {{"id", s.id},         {"version", s.version},
            {"kind", s.kind},     {"permissions", s.permissions},
            {"source", s.source}, {"previous", nullptr}};
  if (s.previous) j["previous"] = *s.previous;
  return j;
}

// A file name as the browser sent it: a plain name of a .mskill, nothing that could name a
// folder.
void check_upload_name(const std::string& name) {
  const bool plain = !name.empty() && name.size() <= 128 && name.find("..") == std::string::npos &&
                     name.find_first_not_of(
                         "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789._-@+") ==
                         std::string::npos &&
                     name.front() != '.' && name.ends_with(".mskill");
  if (!plain)
    throw ApiError(400, "file name '" + name +
                            "' refused: expected a plain name ending in .mskill, like "
                            "hello-1.0.0.mskill (no folders, no '..')");
}

}  // namespace

json parse_body(const std::string& body) {
  try {
    json doc = json::parse(body);
    if (!doc.is_object()) throw ApiError(400, "request body: expected a JSON object");
    return doc;
  } catch (const json::parse_error& e) {
    throw ApiError(400, std::string("request body: not valid JSON (") + e.what() + ")");
  }
}

std::int64_t parse_id(const std::string& text, const char* what) {
  if (text.empty() || text.size() > 18 || text.find_first_not_of("0123456789") != std::string::npos)
    throw ApiError(404, std::string(what) + " id '" + text + "' is not a number");
  return std::stoll(text);
}

std::string url_decode(std::string_view text) {
  std::string out;
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text[i] == '+') {
      out += ' ';
    } else if (text[i] == '%') {
      if (i + 2 >= text.size())
        throw std::runtime_error("bad %-escape at the end of '" + std::string(text) + "'");
      const std::string hex(text.substr(i + 1, 2));
      if (hex.size() != 2 || hex.find_first_not_of("0123456789abcdefABCDEF") != std::string::npos)
        throw std::runtime_error("bad %-escape '%" + hex + "' in '" + std::string(text) + "'");
      out += static_cast<char>(std::stoi(hex, nullptr, 16));
      i += 2;
    } else {
      out += text[i];
    }
  }
  return out;
}

json Api::event_json(std::int64_t id, std::int64_t time_utc_ms, const std::string& kind,
                     const std::string& source, const std::string& message) const {
  return {{"id", id},
          {"time", data::format_local(time_utc_ms, options_.time_zone)},
          {"time_utc_ms", time_utc_ms},
          {"kind", kind},
          {"source", source},
          {"message", message},
          {"photo", !photo_of_event(kind, message).empty()}};
}

ApiResponse Api::handle(const ApiRequest& r) {
  try {
    // /api/<collection>[/<id>[/<action>]]
    std::vector<std::string> parts;
    std::string rest = r.path.substr(r.path.rfind("/api/", 0) == 0 ? 5 : r.path.size());
    for (std::size_t start = 0; start <= rest.size();) {
      const std::size_t slash = rest.find('/', start);
      const std::string part =
          rest.substr(start, slash == std::string::npos ? std::string::npos : slash - start);
      parts.push_back(url_decode(part));
      if (slash == std::string::npos) break;
      start = slash + 1;
    }
    while (parts.size() < 3) parts.emplace_back();
    const std::string& what = parts[0];
    if (what == "status" && r.method == "GET") return status();
    if (what == "reminders") return reminders(r, parts[1]);
    if (what == "contacts") return contacts(r, parts[1]);
    if (what == "skills") {
      if (parts[1] == "install" && r.method == "POST") return install_skill(r);
      return skills(r, parts[1], parts[2]);
    }
    if (what == "events" && r.method == "GET" && !parts[1].empty() && parts[2] == "photo")
      return event_photo(parts[1]);
    if (what == "events" && r.method == "GET") return events(r);
    if (what == "people") return people(r, parts[1]);
    if (what == "devices") return devices(r, parts[1]);
    if (what == "home" && r.method == "GET") return home();
    return {404, {{"error", "no API operation " + r.method + " " + r.path + " (see API.md)"}}};
  } catch (const ApiError& e) {
    return {e.status, {{"error", e.what()}}};
  } catch (const std::exception& e) {
    // The core's refusals name the field or file; they are the user's to read.
    return {422, {{"error", e.what()}}};
  }
}

ApiResponse Api::status() {
  json next = json::array();
  for (const data::Reminder& r : data_.list_reminders()) {
    if (next.size() == 5) break;
    next.push_back(reminder_json(r));
  }
  json recent = json::array();
  for (const data::Event& e : store_.recent_events(5))
    recent.push_back(event_json(e.id, e.time_utc_ms, e.kind, e.source, e.message));
  json live = feed_ ? feed_->snapshot() : json(nullptr);
  return {200,
          {{"running", feed_ != nullptr},
           {"now", data::format_local(std::chrono::duration_cast<std::chrono::milliseconds>(
                                          std::chrono::system_clock::now().time_since_epoch())
                                          .count(),
                                      options_.time_zone)},
           {"time_zone", options_.time_zone},
           {"live", live},
           {"next_reminders", next},
           {"recent_events", recent}}};
}

ApiResponse Api::reminders(const ApiRequest& r, const std::string& id_text) {
  if (r.method == "GET" && id_text.empty()) {
    json list = json::array();
    for (const data::Reminder& rem : data_.list_reminders()) list.push_back(reminder_json(rem));
    return {200, list};
  }
  if (r.method == "DELETE" && !id_text.empty()) {
    const std::int64_t id = parse_id(id_text, "reminder");
    if (!data_.remove_reminder(id))
      throw ApiError(404, "no active reminder with id " + std::to_string(id));
    return {200, {{"removed", id}}};
  }
  if ((r.method == "POST" && id_text.empty()) || (r.method == "PUT" && !id_text.empty())) {
    std::optional<std::int64_t> old;
    if (!id_text.empty()) {
      old = parse_id(id_text, "reminder");
      if (!data_.get_reminder(*old) ||
          data_.get_reminder(*old)->state != data::Reminder::State::kActive)
        throw ApiError(404, "no active reminder with id " + std::to_string(*old));
    }
    const json doc = parse_body(r.body);
    data::Reminder rem;
    rem.title = text_field(doc, "title", true);
    rem.time_zone = text_field(doc, "time_zone", false, options_.time_zone);
    if (rem.time_zone.empty()) rem.time_zone = options_.time_zone;
    rem.recurrence = data::parse_repeat(text_field(doc, "repeat", false, "once"),
                                        text_field(doc, "window", false));
    rem.created_by = "user";
    const std::string at = text_field(doc, "at", true);
    try {
      rem.first_fire_utc_ms = data::local_to_utc_ms(at, rem.time_zone);
    } catch (const std::exception& e) {
      throw ApiError(400, std::string("field 'at': ") + e.what());
    }
    // An edit is the new reminder replacing the old one: added first, so a refusal leaves
    // the old one as it was.
    const std::int64_t id = data_.add_reminder(rem);
    if (old) data_.remove_reminder(*old);
    return {static_cast<unsigned>(old ? 200 : 201), reminder_json(*data_.get_reminder(id))};
  }
  throw ApiError(405, r.method + " " + r.path + ": not an operation on reminders (see API.md)");
}

ApiResponse Api::contacts(const ApiRequest& r, const std::string& id_text) {
  if (r.method == "GET" && id_text.empty()) {
    json list = json::array();
    for (const data::Contact& c : data_.list_contacts()) list.push_back(contact_json(c));
    return {200, list};
  }
  if (r.method == "DELETE" && !id_text.empty()) {
    const std::int64_t id = parse_id(id_text, "contact");
    if (!data_.remove_contact(id)) throw ApiError(404, "no contact with id " + std::to_string(id));
    return {200, {{"removed", id}}};
  }
  if ((r.method == "POST" && id_text.empty()) || (r.method == "PUT" && !id_text.empty())) {
    std::optional<std::int64_t> old;
    if (!id_text.empty()) {
      old = parse_id(id_text, "contact");
      bool found = false;
      for (const data::Contact& c : data_.list_contacts()) found = found || c.id == *old;
      if (!found) throw ApiError(404, "no contact with id " + std::to_string(*old));
    }
    const json doc = parse_body(r.body);
    data::Contact c;
    c.name = text_field(doc, "name", true);
    c.relation = text_field(doc, "relation", false);
    c.phone_numbers = list_field(doc, "phones");
    c.sip_uris = list_field(doc, "sip");
    c.aliases = list_field(doc, "aliases");
    if (auto it = doc.find("emergency"); it != doc.end() && !it->is_null()) {
      if (!it->is_number_integer() || it->get<std::int64_t>() < 0 || it->get<std::int64_t>() > 99)
        throw ApiError(
            400, "field 'emergency': expected a whole number 0..99 (0: not an emergency contact)");
      c.emergency_order = it->get<int>();
    }
    const std::int64_t id = data_.add_contact(c);
    if (old) data_.remove_contact(*old);
    for (const data::Contact& stored : data_.list_contacts())
      if (stored.id == id) return {static_cast<unsigned>(old ? 200 : 201), contact_json(stored)};
    throw ApiError(500, "contact " + std::to_string(id) + " was added but is not listed");
  }
  throw ApiError(405, r.method + " " + r.path + ": not an operation on contacts (see API.md)");
}

ApiResponse Api::skills(const ApiRequest& r, const std::string& id, const std::string& action) {
  if (options_.skills_dir.empty())
    throw ApiError(404, "no skills directory is configured (MARVIN_SKILLS_DIR)");
  store::InstallOptions o;
  o.validate = options_.validate_skill;
  store::Installer installer(options_.skills_dir, o);
  if (r.method == "GET" && id.empty()) {
    json list = json::array();
    for (const store::InstalledSkill& s : installer.list()) list.push_back(skill_json(s));
    return {200, list};
  }
  if (r.method == "POST" && !id.empty() && action == "rollback") {
    if (!installer.find(id)) throw ApiError(404, "skill '" + id + "' is not installed");
    return {200, skill_json(installer.rollback(id))};
  }
  if (r.method == "DELETE" && !id.empty() && action.empty()) {
    if (!installer.find(id)) throw ApiError(404, "skill '" + id + "' is not installed");
    installer.remove(id);
    return {200, {{"removed", id}}};
  }
  throw ApiError(405, r.method + " " + r.path + ": not an operation on skills (see API.md)");
}

ApiResponse Api::install_skill(const ApiRequest& r) {
  if (options_.skills_dir.empty())
    throw ApiError(404, "no skills directory is configured (MARVIN_SKILLS_DIR)");
  auto file = r.query.find("file");
  check_upload_name(file == r.query.end() ? std::string() : file->second);
  if (r.signature.empty())
    throw ApiError(400, "X-Marvin-Signature: missing; send the package's .minisig file with it");
  std::string signature(r.signature.size(), '\0');
  std::size_t signature_size = 0;
  if (sodium_base642bin(reinterpret_cast<unsigned char*>(signature.data()), signature.size(),
                        r.signature.data(), r.signature.size(), nullptr, &signature_size, nullptr,
                        sodium_base64_VARIANT_ORIGINAL) != 0)
    throw ApiError(400,
                   "X-Marvin-Signature: not base64 (expected the .minisig file, base64-encoded)");
  signature.resize(signature_size);
  std::vector<store::PublicKey> keys =
      options_.trusted_keys ? options_.trusted_keys() : std::vector<store::PublicKey>{};
  if (keys.empty())
    throw ApiError(422,
                   "no trusted key to check the package's signature: add the repository "
                   "with `marvin skill repo-add NAME PATH --key KEY.pub`");
  const bool approved = r.query.count("approve") && r.query.at("approve") == "1";

  // The upload goes to its own folder under the state dir, removed afterwards.
  const fs::path folder = options_.state_dir / "uploads" / random_token().substr(0, 16);
  fs::create_directories(folder);
  struct Cleanup {
    fs::path path;
    ~Cleanup() {
      std::error_code ec;
      fs::remove_all(path, ec);
    }
  } cleanup{folder};
  const fs::path package = folder / file->second;
  std::ofstream(package, std::ios::binary)
      .write(r.body.data(), static_cast<std::streamsize>(r.body.size()));
  std::ofstream(package.string() + ".minisig", std::ios::binary) << signature;

  store::InstallOptions o;
  o.validate = options_.validate_skill;
  o.approve = [approved](const store::ApprovalRequest&) { return approved; };
  store::Installer installer(options_.skills_dir, o);
  try {
    const store::InstallResult result =
        installer.install({package, {}, keys, std::nullopt, "upload:" + file->second});
    static const char* kOutcomes[] = {"installed", "upgraded", "downgraded", "already installed"};
    json out = skill_json(result.skill);
    out["outcome"] = kOutcomes[static_cast<int>(result.outcome)];
    return {201, out};
  } catch (const std::exception& e) {
    std::string message = e.what();
    // Name the file the carer uploaded, not the folder it was kept in meanwhile.
    for (std::size_t at; (at = message.find(folder.string() + "/")) != std::string::npos;)
      message.erase(at, folder.string().size() + 1);
    const bool needs_approval = message.find("not approved") != std::string::npos;
    throw ApiError(needs_approval ? 409 : 422, message);
  }
}

ApiResponse Api::events(const ApiRequest& r) {
  std::size_t limit = 50;
  if (auto it = r.query.find("limit"); it != r.query.end()) {
    if (it->second.empty() || it->second.size() > 4 ||
        it->second.find_first_not_of("0123456789") != std::string::npos)
      throw ApiError(400, "limit: expected a number 1..1000, got '" + it->second + "'");
    limit = std::clamp<std::size_t>(std::stoul(it->second), 1, 1000);
  }
  json list = json::array();
  for (const data::Event& e : store_.recent_events(limit))
    list.push_back(event_json(e.id, e.time_utc_ms, e.kind, e.source, e.message));
  return {200, list};
}

}  // namespace marvin::web
