#include "skills/manifest.h"

#include <algorithm>
#include <cctype>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>

namespace marvin::skills {
namespace {

using nlohmann::json;

const char* type_name(const json& value) {
  switch (value.type()) {
    case json::value_t::null:
      return "null";
    case json::value_t::object:
      return "an object";
    case json::value_t::array:
      return "an array";
    case json::value_t::string:
      return "a string";
    case json::value_t::boolean:
      return "a boolean";
    case json::value_t::number_integer:
    case json::value_t::number_unsigned:
      return "an integer";
    case json::value_t::number_float:
      return "a number";
    default:
      return "something else";
  }
}

// Walks a document keeping the JSON path of where it is, so every error names the field.
class Reader {
 public:
  Reader(const std::string& file) : file_(file) {}

  [[noreturn]] void fail(const std::string& path, const std::string& problem) const {
    throw ManifestError(file_, path, problem);
  }

  const json& member(const json& object, const std::string& path, const char* key,
                     json::value_t type, const char* expected) const {
    auto it = object.find(key);
    std::string child = path + "." + key;
    if (it == object.end()) fail(child, std::string("missing required field (") + expected + ")");
    check_type(*it, child, type, expected);
    return *it;
  }

  const json* optional(const json& object, const std::string& path, const char* key,
                       json::value_t type, const char* expected) const {
    auto it = object.find(key);
    if (it == object.end()) return nullptr;
    check_type(*it, path + "." + key, type, expected);
    return &*it;
  }

  void check_type(const json& value, const std::string& path, json::value_t type,
                  const char* expected) const {
    bool ok = value.type() == type ||
              (type == json::value_t::number_integer && value.is_number_unsigned());
    if (!ok) fail(path, std::string("expected ") + expected + ", got " + type_name(value));
  }

  std::string text(const json& object, const std::string& path, const char* key) const {
    std::string value =
        member(object, path, key, json::value_t::string, "a string").get<std::string>();
    if (value.empty()) fail(path + "." + key, "must not be empty");
    return value;
  }

 private:
  std::string file_;
};

SemVer parse_semver(const Reader& reader, const std::string& path, const std::string& text) {
  static const std::regex pattern(
      R"(^(0|[1-9][0-9]*)\.(0|[1-9][0-9]*)\.(0|[1-9][0-9]*)(-[0-9A-Za-z.-]+)?(\+[0-9A-Za-z.-]+)?$)");
  std::smatch m;
  if (!std::regex_match(text, m, pattern) || m[1].length() > 6 || m[2].length() > 6 ||
      m[3].length() > 6) {
    reader.fail(path, "expected a semantic version MAJOR.MINOR.PATCH such as \"1.0.0\", got \"" +
                          text + "\"");
  }
  return SemVer{std::stoi(m[1]), std::stoi(m[2]), std::stoi(m[3]), text};
}

ApiVersion parse_api_version(const Reader& reader, const std::string& path,
                             const std::string& text) {
  static const std::regex pattern(R"(^(0|[1-9][0-9]{0,4})\.(0|[1-9][0-9]{0,4})$)");
  std::smatch m;
  if (!std::regex_match(text, m, pattern)) {
    reader.fail(path, "expected an API version MAJOR.MINOR such as \"1.0\", got \"" + text + "\"");
  }
  return ApiVersion{std::stoi(m[1]), std::stoi(m[2])};
}

bool less(ApiVersion a, ApiVersion b) {
  return a.major != b.major ? a.major < b.major : a.minor < b.minor;
}

SlotKind parse_slot_kind(const Reader& reader, const std::string& path, const std::string& text) {
  static const std::pair<const char*, SlotKind> kinds[] = {
      {"number", SlotKind::kNumber},     {"duration", SlotKind::kDuration},
      {"datetime", SlotKind::kDateTime}, {"contact", SlotKind::kContact},
      {"list", SlotKind::kList},         {"text", SlotKind::kText}};
  for (const auto& [name, kind] : kinds) {
    if (text == name) return kind;
  }
  reader.fail(path, "expected one of number, duration, datetime, contact, list, text; got \"" +
                        text + "\"");
}

// A light syntax check of one utterance template, so a broken template is reported with
// the manifest's file and path before the interpreter sees it: brackets balance, slots
// are declared, alternatives are not empty. Positions are 1-based characters.
void check_template(const Reader& reader, const std::string& path, const std::string& text,
                    const std::set<std::string>& slot_names) {
  auto fail_at = [&](std::size_t index, const std::string& problem) {
    reader.fail(path, "template \"" + text + "\" at position " + std::to_string(index + 1) + ": " +
                          problem);
  };
  std::vector<std::pair<char, std::size_t>> open;
  bool has_word = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    char c = text[i];
    if (c == '(' || c == '[') {
      open.emplace_back(c, i);
    } else if (c == ')' || c == ']') {
      char want = c == ')' ? '(' : '[';
      if (open.empty() || open.back().first != want) {
        fail_at(i, std::string("'") + c + "' closes nothing");
      }
      open.pop_back();
    } else if (c == '{') {
      std::size_t close = text.find('}', i);
      if (close == std::string::npos) fail_at(i, "'{' is never closed");
      std::string name = text.substr(i + 1, close - i - 1);
      if (name.empty()) fail_at(i, "empty slot name '{}'");
      if (name.find_first_of("{[()]") != std::string::npos) {
        fail_at(i, "slot name \"" + name + "\" contains a bracket");
      }
      if (!slot_names.count(name)) {
        fail_at(i, "slot {" + name + "} is not declared in this intent's \"slots\"");
      }
      i = close;
      has_word = true;
    } else if (c == '}') {
      fail_at(i, "'}' closes nothing");
    } else if (c == '|' && (open.empty())) {
      fail_at(i, "'|' outside of (...) or [...]");
    } else if (std::isalnum(static_cast<unsigned char>(c))) {
      has_word = true;
    }
    if (c == '|' || c == ')' || c == ']') {
      // "(a||b)" or "(a|)" leave an empty alternative.
      std::size_t j = i;
      while (j > 0 && text[j - 1] == ' ') --j;
      if (c != ']' && j > 0 && (text[j - 1] == '|' || text[j - 1] == '(')) {
        fail_at(i, "empty alternative");
      }
    }
  }
  if (!open.empty()) {
    fail_at(open.back().second, std::string("'") + open.back().first + "' is never closed");
  }
  if (!has_word) reader.fail(path, "template \"" + text + "\" has no words");
}

}  // namespace

ManifestError::ManifestError(const std::string& file, const std::string& json_path,
                             const std::string& problem)
    : std::runtime_error(file + ": " + json_path + ": " + problem),
      file_(file),
      json_path_(json_path) {}

const char* to_string(SlotKind kind) {
  switch (kind) {
    case SlotKind::kNumber:
      return "number";
    case SlotKind::kDuration:
      return "duration";
    case SlotKind::kDateTime:
      return "datetime";
    case SlotKind::kContact:
      return "contact";
    case SlotKind::kList:
      return "list";
    case SlotKind::kText:
      return "text";
  }
  return "?";
}

const std::vector<std::string>& known_permissions() {
  static const std::vector<std::string> all = {"speech",   "light",    "motion",  "sensors",
                                               "schedule", "contacts", "storage", "vision",
                                               "phone",    "smarthome", "camera",  "faces",
                                               "events"};
  return all;
}

const SlotDecl* IntentDecl::slot(const std::string& slot_name) const {
  for (const SlotDecl& s : slots) {
    if (s.name == slot_name) return &s;
  }
  return nullptr;
}

bool Manifest::has_permission(const std::string& permission) const {
  return permission == "speech" ||
         std::find(permissions.begin(), permissions.end(), permission) != permissions.end();
}

const IntentDecl* Manifest::intent(const std::string& intent_name) const {
  for (const IntentDecl& i : intents) {
    if (i.name == intent_name) return &i;
  }
  return nullptr;
}

bool Manifest::accepts_host_api(ApiVersion host) const {
  return !less(host, host_api_min) && !less(host_api_max, host);
}

Manifest parse_manifest(const json& document, const std::string& file) {
  Reader r(file);
  r.check_type(document, "$", json::value_t::object, "an object");
  Manifest m;
  m.file = file;
  m.raw = document;

  m.id = r.text(document, "$", "id");
  static const std::regex id_pattern("^[a-z0-9][a-z0-9._-]{0,63}$");
  if (!std::regex_match(m.id, id_pattern)) {
    r.fail("$.id", "expected lower-case letters, digits, '.', '_' or '-' (at most 64), got \"" +
                       m.id + "\"");
  }
  m.name = r.text(document, "$", "name");
  m.version = parse_semver(r, "$.version", r.text(document, "$", "version"));
  m.kind = r.text(document, "$", "kind");
  if (m.kind != "native" && m.kind != "lua") {
    r.fail("$.kind", "expected \"native\" or \"lua\", got \"" + m.kind + "\"");
  }
  if (const json* entry = r.optional(document, "$", "entry", json::value_t::string, "a string")) {
    m.entry = entry->get<std::string>();
    if (m.entry.empty() || m.entry.find("..") != std::string::npos || m.entry.front() == '/') {
      r.fail("$.entry", "expected a file name inside the skill's folder, got \"" + m.entry + "\"");
    }
  } else {
    m.entry = m.kind == "native" ? "skill.so" : "main.lua";
  }

  const json& api = r.member(document, "$", "host_api", json::value_t::object, "an object");
  m.host_api_min = parse_api_version(r, "$.host_api.min", r.text(api, "$.host_api", "min"));
  if (const json* max = r.optional(api, "$.host_api", "max", json::value_t::string, "a string")) {
    m.host_api_max = parse_api_version(r, "$.host_api.max", max->get<std::string>());
    if (less(m.host_api_max, m.host_api_min)) {
      r.fail("$.host_api.max", "is older than \"min\"");
    }
  } else {
    m.host_api_max = ApiVersion{m.host_api_min.major, 99999};
  }

  if (const json* perms =
          r.optional(document, "$", "permissions", json::value_t::array, "an array of strings")) {
    for (std::size_t i = 0; i < perms->size(); ++i) {
      std::string path = "$.permissions[" + std::to_string(i) + "]";
      r.check_type((*perms)[i], path, json::value_t::string, "a string");
      std::string p = (*perms)[i].get<std::string>();
      const auto& known = known_permissions();
      if (std::find(known.begin(), known.end(), p) == known.end()) {
        std::string list;
        for (const auto& k : known) list += (list.empty() ? "" : ", ") + k;
        r.fail(path, "unknown permission \"" + p + "\" (known: " + list + ")");
      }
      m.permissions.push_back(p);
    }
  }

  const json& intents = r.member(document, "$", "intents", json::value_t::array, "an array");
  if (intents.empty()) r.fail("$.intents", "a skill needs at least one intent");
  for (std::size_t i = 0; i < intents.size(); ++i) {
    std::string path = "$.intents[" + std::to_string(i) + "]";
    const json& in = intents[i];
    r.check_type(in, path, json::value_t::object, "an object");
    IntentDecl intent;
    intent.name = r.text(in, path, "name");
    if (m.intent(intent.name))
      r.fail(path + ".name", "intent \"" + intent.name + "\" is declared twice");

    std::set<std::string> slot_names;
    if (const json* slots = r.optional(in, path, "slots", json::value_t::array, "an array")) {
      for (std::size_t s = 0; s < slots->size(); ++s) {
        std::string sp = path + ".slots[" + std::to_string(s) + "]";
        const json& sj = (*slots)[s];
        r.check_type(sj, sp, json::value_t::object, "an object");
        SlotDecl slot;
        slot.name = r.text(sj, sp, "name");
        if (!slot_names.insert(slot.name).second) {
          r.fail(sp + ".name", "slot \"" + slot.name + "\" is declared twice");
        }
        slot.kind = parse_slot_kind(r, sp + ".type", r.text(sj, sp, "type"));
        if (const json* values = r.optional(sj, sp, "values", json::value_t::array, "an array")) {
          for (std::size_t v = 0; v < values->size(); ++v) {
            std::string vp = sp + ".values[" + std::to_string(v) + "]";
            r.check_type((*values)[v], vp, json::value_t::string, "a string");
            slot.values.push_back((*values)[v].get<std::string>());
          }
        }
        if (slot.kind == SlotKind::kList && slot.values.empty()) {
          r.fail(sp + ".values", "a slot of type list needs a non-empty \"values\" array");
        }
        if (const json* req =
                r.optional(sj, sp, "required", json::value_t::boolean, "true or false")) {
          slot.required = req->get<bool>();
        }
        if (const json* q = r.optional(sj, sp, "question", json::value_t::string, "a string")) {
          slot.question = q->get<std::string>();
        }
        if (slot.required && slot.question.empty()) {
          r.fail(sp + ".question", "a required slot needs the question to ask when it is missing");
        }
        intent.slots.push_back(std::move(slot));
      }
    }

    const json& templates =
        r.member(in, path, "templates", json::value_t::array, "an array of strings");
    if (templates.empty()) r.fail(path + ".templates", "an intent needs at least one template");
    for (std::size_t t = 0; t < templates.size(); ++t) {
      std::string tp = path + ".templates[" + std::to_string(t) + "]";
      r.check_type(templates[t], tp, json::value_t::string, "a string");
      std::string text = templates[t].get<std::string>();
      check_template(r, tp, text, slot_names);
      intent.templates.push_back(std::move(text));
    }

    if (const json* d = r.optional(in, path, "description", json::value_t::string, "a string")) {
      intent.description = d->get<std::string>();
    }
    if (const json* examples = r.optional(in, path, "examples", json::value_t::array,
                                          "an array of sentences")) {
      for (std::size_t e = 0; e < examples->size(); ++e) {
        std::string ep = path + ".examples[" + std::to_string(e) + "]";
        r.check_type((*examples)[e], ep, json::value_t::string, "a string");
        std::string text = (*examples)[e].get<std::string>();
        if (text.find_first_not_of(" \t") == std::string::npos) r.fail(ep, "must not be empty");
        if (text.size() > 500) r.fail(ep, "longer than 500 bytes (an example is one sentence)");
        intent.examples.push_back(std::move(text));
      }
    }
    if (const json* synonyms = r.optional(in, path, "synonyms", json::value_t::object,
                                          "an object of word: [words people say instead]")) {
      for (const auto& [word, said] : synonyms->items()) {
        std::string sp = path + ".synonyms." + word;
        if (word.empty()) r.fail(sp, "the word must not be empty");
        r.check_type(said, sp, json::value_t::array, "an array of strings");
        std::vector<std::string> alternatives;
        for (std::size_t k = 0; k < said.size(); ++k) {
          std::string kp = sp + "[" + std::to_string(k) + "]";
          r.check_type(said[k], kp, json::value_t::string, "a string");
          if (said[k].get<std::string>().empty()) r.fail(kp, "must not be empty");
          alternatives.push_back(said[k].get<std::string>());
        }
        intent.synonyms.emplace_back(word, std::move(alternatives));
      }
    }

    if (const json* c = r.optional(in, path, "confirm", json::value_t::boolean, "true or false")) {
      intent.confirm = c->get<bool>();
    }
    if (const json* q =
            r.optional(in, path, "confirm_question", json::value_t::string, "a string")) {
      intent.confirm_question = q->get<std::string>();
    }
    if (const json* t = r.optional(in, path, "stopped", json::value_t::string, "a string")) {
      intent.stopped = t->get<std::string>();
    }
    if (const json* u = r.optional(in, path, "urgent", json::value_t::boolean, "true or false")) {
      intent.urgent = u->get<bool>();
    }
    if (intent.confirm && intent.confirm_question.empty()) {
      intent.confirm_question = "Shall I go ahead?";
    }
    if (const json* e = r.optional(in, path, "execution", json::value_t::string, "a string")) {
      std::string text = e->get<std::string>();
      if (text == "short") {
        intent.execution = Execution::kShort;
      } else if (text == "long") {
        intent.execution = Execution::kLong;
      } else {
        r.fail(path + ".execution", "expected \"short\" or \"long\", got \"" + text + "\"");
      }
    }
    if (const json* limit =
            r.optional(in, path, "time_limit_s", json::value_t::number_integer, "an integer")) {
      std::int64_t seconds = limit->get<std::int64_t>();
      if (seconds < 1 || seconds > 24 * 3600) {
        r.fail(path + ".time_limit_s",
               "expected 1 to 86400 seconds, got " + std::to_string(seconds));
      }
      intent.time_limit_ms = seconds * 1000;
    }
    m.intents.push_back(std::move(intent));
  }
  return m;
}

Manifest load_manifest(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ManifestError(path.string(), "$", "cannot read the file");
  std::stringstream buffer;
  buffer << in.rdbuf();
  json document;
  try {
    document = json::parse(buffer.str());
  } catch (const json::parse_error& e) {
    throw ManifestError(path.string(), "$",
                        "not valid JSON at byte " + std::to_string(e.byte) + " (" + e.what() + ")");
  }
  Manifest m = parse_manifest(document, path.string());
  m.file = path;
  return m;
}

}  // namespace marvin::skills
