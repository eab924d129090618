#include "store/installer.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "common/log.h"
#include "marvin/abi.h"
#include "store/package.h"
#include "store/util.h"

namespace marvin::store {
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

constexpr const char* kVersionsDir = "versions";
constexpr const char* kReceiptsDir = "receipts";
constexpr const char* kCurrent = "current";
constexpr const char* kPrevious = "previous";

[[noreturn]] void fail(const std::string& what) { throw std::runtime_error(what); }

// The version a pointer (`current` or `previous`) names, or nothing if there is none.
std::optional<std::string> read_pointer(const fs::path& link) {
  std::error_code ec;
  if (!fs::is_symlink(fs::symlink_status(link, ec))) return std::nullopt;
  fs::path target = fs::read_symlink(link, ec);
  if (ec) return std::nullopt;
  auto it = target.begin();
  if (it == target.end() || *it != kVersionsDir) return std::nullopt;
  ++it;
  if (it == target.end()) return std::nullopt;
  std::string version = it->string();
  if (++it != target.end()) return std::nullopt;
  return version;
}

// Points `link` at versions/<version> atomically: a new symlink beside it, renamed over it.
void set_pointer(const fs::path& link, const std::string& version, bool durable) {
  fs::path tmp = link.string() + ".tmp";
  ::unlink(tmp.c_str());
  std::string target = std::string(kVersionsDir) + "/" + version;
  if (::symlink(target.c_str(), tmp.c_str()) != 0) {
    fail(tmp.string() + ": cannot create symlink: " + std::strerror(errno));
  }
  if (::rename(tmp.c_str(), link.c_str()) != 0) {
    fail(link.string() + ": cannot replace: " + std::strerror(errno));
  }
  if (durable) sync_path(link.parent_path());
}

bool is_store_skill_dir(const fs::path& p) {
  std::error_code ec;
  return fs::is_directory(fs::symlink_status(p, ec)) && p.filename().string().front() != '.' &&
         (fs::exists(p / kVersionsDir, ec) || fs::exists(p / kReceiptsDir, ec) ||
          fs::is_symlink(fs::symlink_status(p / kCurrent, ec)));
}

json receipt_json(const InstalledSkill& s) {
  return {{"id", s.id},         {"version", s.version},         {"digest", s.digest},
          {"kind", s.kind},     {"permissions", s.permissions}, {"source", s.source}};
}

std::optional<InstalledSkill> read_receipt(const fs::path& id_dir, const std::string& version) {
  fs::path p = id_dir / kReceiptsDir / (version + ".json");
  std::error_code ec;
  if (!fs::exists(p, ec)) return std::nullopt;
  try {
    json j = json::parse(read_text_file(p));
    InstalledSkill s;
    s.id = j.at("id").get<std::string>();
    s.version = j.at("version").get<std::string>();
    s.digest = j.at("digest").get<std::string>();
    s.kind = j.at("kind").get<std::string>();
    s.permissions = j.at("permissions").get<std::vector<std::string>>();
    s.source = j.at("source").get<std::string>();
    return s;
  } catch (const std::exception& e) {
    log(LogLevel::kWarning, "store", p.string() + ": unreadable install receipt: " + e.what());
    return std::nullopt;
  }
}

std::vector<std::string> set_difference(const std::vector<std::string>& a, const std::vector<std::string>& b) {
  std::vector<std::string> out;
  for (const std::string& x : a) {
    if (std::find(b.begin(), b.end(), x) == b.end()) out.push_back(x);
  }
  return out;
}

void remove_tree(const fs::path& p) {
  std::error_code ec;
  fs::remove_all(p, ec);
  if (ec) fail(p.string() + ": cannot remove: " + ec.message());
}

}  // namespace

Version InstallOptions::default_host_api() {
  return parse_version(std::to_string(MARVIN_ABI_MAJOR) + "." + std::to_string(MARVIN_ABI_MINOR),
                       "host API", /*allow_short=*/true);
}

// Exclusive flock() on <skills-dir>/.store/lock for the life of the object.
class Installer::Lock {
 public:
  explicit Lock(const fs::path& file) {
    fd_ = ::open(file.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd_ < 0) fail(file.string() + ": cannot open: " + std::strerror(errno));
    while (::flock(fd_, LOCK_EX) != 0) {
      if (errno != EINTR) {
        ::close(fd_);
        fail(file.string() + ": cannot lock: " + std::strerror(errno));
      }
    }
  }
  ~Lock() { ::close(fd_); }
  Lock(const Lock&) = delete;
  Lock& operator=(const Lock&) = delete;

 private:
  int fd_ = -1;
};

Installer::Installer(fs::path skills_dir, InstallOptions options)
    : dir_(std::move(skills_dir)), options_(std::move(options)) {
  fs::create_directories(store_dir() / "staging");
}

void Installer::step(std::string_view name) const {
  if (options_.step_hook) options_.step_hook(name);
}

void Installer::recover() {
  Lock lock(store_dir() / "lock");
  recover_locked();
}

void Installer::recover_locked() {
  // 1. Staging directories of interrupted installs: never active, delete.
  for (const auto& e : fs::directory_iterator(store_dir() / "staging")) remove_tree(e.path());
  // 2. Per skill: temporary pointers, skills never activated or half removed, versions no
  //    pointer names.
  for (const auto& e : fs::directory_iterator(dir_)) {
    const fs::path& id_dir = e.path();
    if (!is_store_skill_dir(id_dir)) continue;
    std::error_code ec;
    fs::remove(id_dir / (std::string(kCurrent) + ".tmp"), ec);
    fs::remove(id_dir / (std::string(kPrevious) + ".tmp"), ec);
    std::optional<std::string> current = read_pointer(id_dir / kCurrent);
    if (!current || !fs::is_directory(id_dir / kVersionsDir / *current)) {
      // Not active (a first install cut short, or a removal cut short): delete.
      remove_tree(id_dir);
      continue;
    }
    std::optional<std::string> previous = read_pointer(id_dir / kPrevious);
    if (previous && (!fs::is_directory(id_dir / kVersionsDir / *previous) ||
                     !read_receipt(id_dir, *previous) || *previous == *current)) {
      fs::remove(id_dir / kPrevious, ec);
      previous.reset();
    }
    for (const auto& v : fs::directory_iterator(id_dir / kVersionsDir)) {
      std::string name = v.path().filename().string();
      if (name != *current && (!previous || name != *previous)) remove_tree(v.path());
    }
    if (fs::is_directory(id_dir / kReceiptsDir)) {
      for (const auto& r : fs::directory_iterator(id_dir / kReceiptsDir)) {
        std::string name = r.path().stem().string();
        if (name != *current && (!previous || name != *previous)) fs::remove(r.path(), ec);
      }
    }
  }
  // 3. The lock file follows the pointers.
  write_lock_file();
}

void Installer::write_lock_file() {
  json skills = json::object();
  std::vector<fs::path> ids;
  for (const auto& e : fs::directory_iterator(dir_)) {
    if (is_store_skill_dir(e.path())) ids.push_back(e.path());
  }
  std::sort(ids.begin(), ids.end());
  for (const fs::path& id_dir : ids) {
    std::optional<std::string> current = read_pointer(id_dir / kCurrent);
    if (!current) continue;
    std::optional<InstalledSkill> s = read_receipt(id_dir, *current);
    if (!s) continue;
    json entry = receipt_json(*s);
    if (std::optional<std::string> prev = read_pointer(id_dir / kPrevious)) entry["previous"] = *prev;
    skills[s->id] = entry;
  }
  std::string text = json{{"format", 1}, {"skills", skills}}.dump(2) + "\n";
  std::error_code ec;
  if (fs::exists(lock_file(), ec) && read_text_file(lock_file()) == text) return;
  write_file_atomic(lock_file(), text);
}

std::vector<InstalledSkill> Installer::list() const {
  std::vector<InstalledSkill> out;
  std::error_code ec;
  if (!fs::exists(lock_file(), ec)) return out;
  json j;
  try {
    j = json::parse(read_text_file(lock_file()));
  } catch (const json::parse_error& e) {
    fail(lock_file().string() + ": not valid JSON: " + e.what());
  }
  auto skills = j.find("skills");
  if (skills == j.end() || !skills->is_object()) fail(lock_file().string() + ": skills: missing");
  for (const auto& [id, entry] : skills->items()) {
    InstalledSkill s;
    s.id = id;
    s.version = entry.value("version", "");
    s.digest = entry.value("digest", "");
    s.kind = entry.value("kind", "");
    s.permissions = entry.value("permissions", std::vector<std::string>{});
    s.source = entry.value("source", "");
    if (entry.contains("previous")) s.previous = entry["previous"].get<std::string>();
    s.path = dir_ / id / kCurrent;
    out.push_back(std::move(s));
  }
  return out;
}

std::optional<InstalledSkill> Installer::find(const std::string& id) const {
  for (InstalledSkill& s : list()) {
    if (s.id == id) return s;
  }
  return std::nullopt;
}

InstallResult Installer::install(const PackageSource& source) {
  Lock lock(store_dir() / "lock");
  recover_locked();
  const std::string origin = source.package.string();

  // 1. The bytes: size and digest against the index, then the signature.
  Bytes bytes = read_file(source.package, options_.limits.max_total_bytes);
  std::string digest = sha256_digest(bytes);
  if (source.expected) {
    const IndexEntry& want = *source.expected;
    if (bytes.size() != want.size) {
      fail(origin + ": size is " + std::to_string(bytes.size()) + " bytes, the index says " +
           std::to_string(want.size));
    }
    if (digest != want.digest) fail(origin + ": digest " + digest + " differs from the index's " + want.digest);
  }
  fs::path sig_path = source.signature.empty() ? signature_path_for(source.package) : source.signature;
  std::error_code ec;
  if (!fs::exists(sig_path, ec)) fail(sig_path.string() + ": missing signature for " + origin);
  PackageClaim claim =
      verify_package_signature(bytes, read_text_file(sig_path, 4096), source.trusted_keys, origin);
  if (source.expected && claim.id_at_version() != source.expected->id + "@" + source.expected->version.text) {
    fail(sig_path.string() + ": signature is for " + claim.id_at_version() + ", the index entry is " +
         source.expected->id + "@" + source.expected->version.text);
  }
  if (!is_valid_skill_id(claim.id)) fail(sig_path.string() + ": trusted comment names an invalid skill id");
  Version new_version = parse_version(claim.version, sig_path.string() + ": trusted comment version");

  // 2. Against what is installed: same version, downgrade.
  std::optional<InstalledSkill> installed = find(claim.id);
  std::optional<InstallResult::Outcome> outcome;
  if (installed) {
    int c = compare_versions(new_version, parse_version(installed->version, lock_file().string()));
    if (c == 0 && installed->digest == digest) {
      return InstallResult{InstallResult::Outcome::kAlreadyInstalled, *installed, std::nullopt};
    }
    if (c == 0) {
      fail(origin + ": " + claim.id_at_version() + " is installed with other content (digest " + installed->digest +
           "); a version's content never changes: publish a new version");
    }
    if (c < 0 && !options_.allow_downgrade) {
      fail(origin + ": " + claim.id_at_version() + " is older than the installed " + installed->version +
           "; use `marvin skill rollback " + claim.id + "` or --allow-downgrade");
    }
    outcome = c < 0 ? InstallResult::Outcome::kDowngraded : InstallResult::Outcome::kUpgraded;
  } else {
    outcome = InstallResult::Outcome::kInstalled;
  }

  // 3. Stage: extract into a fresh directory inside the skills directory (same file
  //    system, so activation is a rename).
  std::string tmpl = (store_dir() / "staging" / (claim.id + "-XXXXXX")).string();
  if (::mkdtemp(tmpl.data()) == nullptr) fail(tmpl + ": cannot create staging directory: " + std::strerror(errno));
  fs::path staged = tmpl;
  struct StagingGuard {
    fs::path path;
    ~StagingGuard() {
      std::error_code e;
      if (!path.empty()) fs::remove_all(path, e);
    }
  } guard{staged};
  step("stage");
  extract_archive(bytes, staged, options_.limits, origin, options_.durable, options_.step_hook);
  step("staged");

  // 4. Manifest, host API, architecture, the host's own validation.
  fs::path manifest_path = staged / "skill.json";
  if (!fs::is_regular_file(fs::symlink_status(manifest_path, ec))) fail(origin + ": skill.json missing from the package");
  PackageManifest manifest = parse_package_manifest(read_text_file(manifest_path), origin + ": skill.json");
  if (manifest.id != claim.id) {
    fail(origin + ": skill.json: id: \"" + manifest.id + "\" differs from the signed id \"" + claim.id + "\"");
  }
  if (manifest.version.text != claim.version) {
    fail(origin + ": skill.json: version: \"" + manifest.version.text + "\" differs from the signed version \"" +
         claim.version + "\"");
  }
  if (source.expected) {
    if (manifest.permissions != source.expected->permissions) {
      fail(origin + ": skill.json: permissions differ from the repository index");
    }
  }
  if (!manifest.host_api.contains(options_.host_api)) {
    fail(origin + ": skill.json: host_api: the skill needs host API \"" + manifest.host_api.text() +
         "\", this host provides " + options_.host_api.text);
  }
  if (manifest.kind == "native") {
    fs::path lib = staged / manifest.library;
    if (!fs::is_regular_file(fs::symlink_status(lib, ec))) {
      fail(origin + ": skill.json: library: \"" + manifest.library + "\" is not in the package");
    }
    ElfArch arch = read_elf_arch(read_file(lib, 64 * 1024 * 1024), origin + ": " + manifest.library);
    if (!(arch == options_.host_arch)) {
      fail(origin + ": " + manifest.library + ": built for " + arch.name() + ", this host is " +
           options_.host_arch.name());
    }
  }
  if (options_.validate) {
    try {
      options_.validate(staged);
    } catch (const std::exception& e) {
      fail(origin + ": the host would not load it: " + e.what());
    }
  }

  // 5. Permissions.
  std::vector<std::string> added =
      installed ? set_difference(manifest.permissions, installed->permissions) : manifest.permissions;
  if (!added.empty() && !options_.assume_yes) {
    ApprovalRequest req{manifest.id, manifest.version.text,
                        installed ? std::optional<std::string>(installed->version) : std::nullopt,
                        manifest.permissions, added};
    if (!options_.approve || !options_.approve(req)) {
      std::string list;
      for (const std::string& p : added) list += (list.empty() ? "" : ", ") + p;
      fail(manifest.id_at_version() + ": permissions not approved (" + list + "); approve them or pass --yes");
    }
  }

  // 6. Activate. Each step leaves a state recover() turns into "old active" (before the
  //    `current` rename) or "new active" (after it).
  const fs::path id_dir = dir_ / manifest.id;
  const std::string& version = manifest.version.text;
  step("prepare");
  fs::create_directories(id_dir / kVersionsDir);
  fs::create_directories(id_dir / kReceiptsDir);
  InstalledSkill record{manifest.id, version, digest, manifest.kind, manifest.permissions,
                        source.source_label.empty() ? "file:" + fs::absolute(source.package).string() : source.source_label,
                        installed ? std::optional<std::string>(installed->version) : std::nullopt,
                        id_dir / kCurrent};
  if (fs::exists(fs::symlink_status(id_dir / kVersionsDir / version, ec))) {
    // An older copy of this version that is not current (e.g. the previous one): the
    // pointer to it goes first so it is never dangling.
    if (read_pointer(id_dir / kPrevious) == version) fs::remove(id_dir / kPrevious);
    remove_tree(id_dir / kVersionsDir / version);
  }
  write_file_atomic(id_dir / kReceiptsDir / (version + ".json"), receipt_json(record).dump(2) + "\n");
  step("receipt written");
  if (::rename(staged.c_str(), (id_dir / kVersionsDir / version).c_str()) != 0) {
    fail((id_dir / kVersionsDir / version).string() + ": cannot move staged skill: " + std::strerror(errno));
  }
  guard.path.clear();
  if (options_.durable) {
    sync_path(id_dir / kVersionsDir);
    sync_path(store_dir() / "staging");
  }
  step("version in place");
  if (installed) {
    set_pointer(id_dir / kPrevious, installed->version, options_.durable);
    step("previous pointer set");
  }
  set_pointer(id_dir / kCurrent, version, options_.durable);  // the commit point
  step("current pointer switched");
  write_lock_file();
  step("lock written");
  // Versions older than the previous one are no longer reachable.
  for (const auto& v : fs::directory_iterator(id_dir / kVersionsDir)) {
    std::string name = v.path().filename().string();
    if (name != version && (!installed || name != installed->version)) {
      remove_tree(v.path());
      fs::remove(id_dir / kReceiptsDir / (name + ".json"), ec);
    }
  }
  step("cleaned up");
  log(LogLevel::kInfo, "store",
      "installed " + manifest.id_at_version() + (installed ? " (was " + installed->version + ")" : ""));
  if (options_.on_change) {
    SkillChange::Kind kind = *outcome == InstallResult::Outcome::kInstalled  ? SkillChange::Kind::kInstalled
                             : *outcome == InstallResult::Outcome::kUpgraded ? SkillChange::Kind::kUpgraded
                                                                             : SkillChange::Kind::kDowngraded;
    options_.on_change(SkillChange{kind, manifest.id,
                                   installed ? std::optional<std::string>(installed->version) : std::nullopt,
                                   version, id_dir / kCurrent});
  }
  return InstallResult{*outcome, *find(manifest.id),
                       installed ? std::optional<std::string>(installed->version) : std::nullopt};
}

InstalledSkill Installer::rollback(const std::string& id) {
  Lock lock(store_dir() / "lock");
  recover_locked();
  const fs::path id_dir = dir_ / id;
  std::optional<std::string> current = read_pointer(id_dir / kCurrent);
  if (!is_valid_skill_id(id) || !current) fail("skill \"" + id + "\" is not installed");
  std::optional<std::string> previous = read_pointer(id_dir / kPrevious);
  if (!previous) fail("skill \"" + id + "\" has no previous version to roll back to");
  step("rollback: switch current");
  set_pointer(id_dir / kCurrent, *previous, options_.durable);
  step("rollback: current switched");
  set_pointer(id_dir / kPrevious, *current, options_.durable);
  step("rollback: previous switched");
  write_lock_file();
  step("rollback: lock written");
  log(LogLevel::kInfo, "store", "rolled back " + id + " from " + *current + " to " + *previous);
  if (options_.on_change) {
    options_.on_change(SkillChange{SkillChange::Kind::kRolledBack, id, *current, *previous, id_dir / kCurrent});
  }
  return *find(id);
}

void Installer::remove(const std::string& id) {
  Lock lock(store_dir() / "lock");
  recover_locked();
  const fs::path id_dir = dir_ / id;
  std::optional<std::string> current = read_pointer(id_dir / kCurrent);
  if (!is_valid_skill_id(id) || !current) fail("skill \"" + id + "\" is not installed");
  step("remove: unlink current");
  if (::unlink((id_dir / kCurrent).c_str()) != 0) {
    fail((id_dir / kCurrent).string() + ": cannot remove: " + std::strerror(errno));
  }
  if (options_.durable) sync_path(id_dir);
  step("remove: current unlinked");
  write_lock_file();
  step("remove: lock written");
  remove_tree(id_dir);
  log(LogLevel::kInfo, "store", "removed " + id + " " + *current);
  if (options_.on_change) {
    options_.on_change(SkillChange{SkillChange::Kind::kRemoved, id, *current, std::nullopt, id_dir / kCurrent});
  }
}

}  // namespace marvin::store
