#include "store/repository.h"

#include <algorithm>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "store/archive.h"
#include "store/package.h"
#include "store/package_manifest.h"
#include "store/util.h"

namespace marvin::store {
namespace {

using nlohmann::json;

[[noreturn]] void index_error(const std::string& origin, const std::string& path, const std::string& what) {
  throw std::runtime_error(origin + ": " + path + ": " + what);
}

const json& field(const json& j, const std::string& name, json::value_t type, const std::string& origin,
                  const std::string& path) {
  auto it = j.find(name);
  if (it == j.end()) index_error(origin, path + "." + name, "missing");
  bool ok = it->type() == type ||
            (type == json::value_t::number_unsigned && it->type() == json::value_t::number_integer &&
             it->get<std::int64_t>() >= 0);
  if (!ok) index_error(origin, path + "." + name, std::string("wrong type (") + it->type_name() + ")");
  return *it;
}

std::string index_trusted_comment(const std::string& name, std::uint64_t sequence) {
  return "marvin-index " + name + " sequence=" + std::to_string(sequence);
}

}  // namespace

const IndexEntry* RepositoryIndex::find(const std::string& id, const std::string& version) const {
  auto it = skills.find(id);
  if (it == skills.end() || it->second.empty()) return nullptr;
  if (version.empty()) return &it->second.back();
  for (const IndexEntry& e : it->second) {
    if (e.version.text == version) return &e;
  }
  return nullptr;
}

RepositoryIndex parse_index(const std::string& text, const std::string& origin) {
  json j;
  try {
    j = json::parse(text);
  } catch (const json::parse_error& e) {
    throw std::runtime_error(origin + ": not valid JSON: " + e.what());
  }
  if (!j.is_object()) throw std::runtime_error(origin + ": expected a JSON object");
  RepositoryIndex index;
  const json& format = field(j, "format", json::value_t::string, origin, "$");
  if (format.get<std::string>() != "marvin-index/1") index_error(origin, "$.format", "unsupported format \"" + format.get<std::string>() + "\"");
  index.name = field(j, "name", json::value_t::string, origin, "$").get<std::string>();
  index.sequence = field(j, "sequence", json::value_t::number_unsigned, origin, "$").get<std::uint64_t>();
  index.digest = sha256_digest(std::span<const std::uint8_t>(
      reinterpret_cast<const std::uint8_t*>(text.data()), text.size()));
  const json& skills = field(j, "skills", json::value_t::object, origin, "$");
  for (const auto& [id, skill] : skills.items()) {
    std::string spath = "$.skills." + id;
    if (!is_valid_skill_id(id)) index_error(origin, spath, "not a valid skill id");
    if (!skill.is_object()) index_error(origin, spath, "expected an object");
    const json& versions = field(skill, "versions", json::value_t::object, origin, spath);
    std::vector<IndexEntry>& list = index.skills[id];
    for (const auto& [vtext, v] : versions.items()) {
      std::string vpath = spath + ".versions." + vtext;
      if (!v.is_object()) index_error(origin, vpath, "expected an object");
      IndexEntry e;
      e.id = id;
      e.version = parse_version(vtext, origin + ": " + vpath);
      e.file = field(v, "file", json::value_t::string, origin, vpath).get<std::string>();
      if (e.file.empty() || e.file.find('/') != std::string::npos || e.file == "." || e.file == "..") {
        index_error(origin, vpath + ".file", "must be a plain file name");
      }
      e.digest = field(v, "digest", json::value_t::string, origin, vpath).get<std::string>();
      if (e.digest.rfind("sha256:", 0) != 0 || e.digest.size() != 71) index_error(origin, vpath + ".digest", "expected sha256:<64 hex digits>");
      e.size = field(v, "size", json::value_t::number_unsigned, origin, vpath).get<std::uint64_t>();
      e.kind = field(v, "kind", json::value_t::string, origin, vpath).get<std::string>();
      e.host_api = field(v, "host_api", json::value_t::string, origin, vpath).get<std::string>();
      const json& perms = field(v, "permissions", json::value_t::array, origin, vpath);
      for (const json& p : perms) {
        if (!p.is_string()) index_error(origin, vpath + ".permissions", "expected strings");
        e.permissions.push_back(p.get<std::string>());
      }
      list.push_back(std::move(e));
    }
    std::sort(list.begin(), list.end(), [](const IndexEntry& a, const IndexEntry& b) {
      return compare_versions(a.version, b.version) < 0;
    });
  }
  return index;
}

RepositoryIndex verify_index(const std::string& index_text, const std::string& signature_text,
                             const std::vector<PublicKey>& trusted, const std::string& origin) {
  const std::string sig_origin = origin + ".minisig";
  Signature sig = parse_signature(signature_text, sig_origin);
  std::string comment = verify_message(
      std::span<const std::uint8_t>(reinterpret_cast<const std::uint8_t*>(index_text.data()), index_text.size()),
      sig, trusted, sig_origin);
  RepositoryIndex index = parse_index(index_text, origin);
  if (comment != index_trusted_comment(index.name, index.sequence)) {
    throw std::runtime_error(sig_origin + ": trusted comment \"" + comment + "\" does not match the index (expected \"" +
                             index_trusted_comment(index.name, index.sequence) + "\")");
  }
  return index;
}

void SeenIndexes::check_and_record(const RepositoryIndex& index, const std::string& origin) {
  json state = json::object();
  if (std::filesystem::exists(file_)) {
    try {
      state = json::parse(read_text_file(file_));
    } catch (const json::parse_error& e) {
      throw std::runtime_error(file_.string() + ": not valid JSON: " + e.what());
    }
  }
  if (auto it = state.find(index.name); it != state.end() && it->is_object()) {
    std::uint64_t seen = it->value("sequence", std::uint64_t{0});
    std::string seen_digest = it->value("digest", std::string());
    if (index.sequence < seen) {
      throw std::runtime_error(origin + ": sequence: stale index for repository \"" + index.name +
                               "\": sequence " + std::to_string(index.sequence) +
                               " is older than sequence " + std::to_string(seen) + " already seen");
    }
    if (index.sequence == seen) {
      if (index.digest != seen_digest) {
        throw std::runtime_error(origin + ": sequence: replayed index for repository \"" + index.name +
                                 "\": sequence " + std::to_string(seen) +
                                 " was already seen with different content");
      }
      return;
    }
  }
  state[index.name] = {{"sequence", index.sequence}, {"digest", index.digest}};
  std::filesystem::create_directories(file_.parent_path());
  write_file_atomic(file_, state.dump(2) + "\n");
}

Repository open_repository(const RepositoryConfig& config, SeenIndexes* seen) {
  std::filesystem::path index_path = config.path / "index.json";
  std::filesystem::path sig_path = signature_path_for(index_path);
  if (!std::filesystem::exists(index_path)) throw std::runtime_error(index_path.string() + ": missing: not a skill repository");
  if (!std::filesystem::exists(sig_path)) throw std::runtime_error(sig_path.string() + ": missing signature of the index");
  if (config.trusted_keys.empty()) {
    throw std::runtime_error("repository \"" + config.name + "\" (" + config.path.string() + "): no trusted keys configured");
  }
  Repository repo{config, verify_index(read_text_file(index_path), read_text_file(sig_path, 4096),
                                       config.trusted_keys, index_path.string())};
  if (seen != nullptr) seen->check_and_record(repo.index, index_path.string());
  return repo;
}

RepositoryIndex build_repository_index(const std::filesystem::path& dir, const std::string& name,
                                       const SecretKey& key, std::uint64_t sequence,
                                       const std::vector<PublicKey>& extra_trusted) {
  std::vector<PublicKey> trusted = extra_trusted;
  trusted.push_back(key.public_key());
  std::filesystem::path index_path = dir / "index.json";
  if (sequence == 0) {
    sequence = 1;
    if (std::filesystem::exists(index_path)) {
      sequence = parse_index(read_text_file(index_path), index_path.string()).sequence + 1;
    }
  }
  std::vector<std::filesystem::path> packages;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    if (entry.is_regular_file() && entry.path().extension() == ".mskill") packages.push_back(entry.path());
  }
  std::sort(packages.begin(), packages.end());
  json skills = json::object();
  for (const std::filesystem::path& p : packages) {
    Bytes bytes = read_file(p);
    std::filesystem::path sig_path = signature_path_for(p);
    if (!std::filesystem::exists(sig_path)) throw std::runtime_error(sig_path.string() + ": missing; sign the package first");
    PackageClaim claim = verify_package_signature(bytes, read_text_file(sig_path, 4096), trusted, p.string());
    std::map<std::string, Bytes> files = read_archive(bytes, ArchiveLimits{}, p.string());
    auto m = files.find("skill.json");
    if (m == files.end()) throw std::runtime_error(p.string() + ": skill.json missing from the package");
    PackageManifest manifest = parse_package_manifest(std::string(m->second.begin(), m->second.end()),
                                                      p.string() + ": skill.json");
    if (manifest.id_at_version() != claim.id_at_version()) {
      throw std::runtime_error(p.string() + ": skill.json says " + manifest.id_at_version() +
                               " but the signature is for " + claim.id_at_version());
    }
    json& versions = skills[manifest.id]["versions"];
    if (versions.contains(manifest.version.text)) {
      throw std::runtime_error(p.string() + ": " + manifest.id_at_version() + " appears in two packages");
    }
    versions[manifest.version.text] = {{"file", p.filename().string()},
                                       {"digest", claim.digest},
                                       {"size", bytes.size()},
                                       {"kind", manifest.kind},
                                       {"permissions", manifest.permissions},
                                       {"host_api", manifest.host_api.text()}};
  }
  json index = {{"format", "marvin-index/1"}, {"name", name}, {"sequence", sequence}, {"skills", skills}};
  std::string text = index.dump(2) + "\n";
  std::string sig = sign_message(std::span<const std::uint8_t>(
                                     reinterpret_cast<const std::uint8_t*>(text.data()), text.size()),
                                 key, index_trusted_comment(name, sequence), "signature of repository index " + name);
  // Signature first: a reader that sees the new index.json sees its signature too, except
  // in the window between the two renames, where the old signature fails closed.
  write_file_atomic(signature_path_for(index_path), sig);
  write_file_atomic(index_path, text);
  return parse_index(text, index_path.string());
}

}  // namespace marvin::store
