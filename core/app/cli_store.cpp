// `marvin skill pack|index|repo-add|search|info|install|upgrade|remove|rollback|list`: the
// skill store's commands (store/README.md). The Lua tools add `new|test|run` to the same
// `skill` group.
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "app/cli.h"
#include "app/installed_skills.h"
#include "store/installer.h"
#include "store/package.h"
#include "store/repository.h"
#include "store/util.h"

namespace marvin::app {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

struct StoreArgs {
  std::string skills_dir;
  std::vector<std::string> repos;
  std::vector<std::string> keys;
  bool yes = false;
  bool allow_downgrade = false;
  std::string target;
  std::string sign_key;
  std::string output;
  std::string name;
  std::uint64_t sequence = 0;
};

fs::path skills_dir(const StoreArgs& a) {
  if (!a.skills_dir.empty()) return a.skills_dir;
  if (std::optional<fs::path> dir = default_installed_skills_dir()) return *dir;
  throw CliError("no skills directory: pass --skills-dir or set MARVIN_SKILLS_DIR");
}

fs::path repositories_file(const StoreArgs& a) { return skills_dir(a) / ".store" / "repositories.json"; }

json load_repositories(const StoreArgs& a) {
  fs::path f = repositories_file(a);
  if (!fs::exists(f)) return json::object();
  return json::parse(store::read_text_file(f));
}

std::vector<store::PublicKey> key_files(const StoreArgs& a) {
  std::vector<store::PublicKey> keys;
  for (const std::string& k : a.keys) keys.push_back(store::load_public_key(k));
  return keys;
}

store::RepositoryConfig repo_config(const StoreArgs& a, const std::string& name_or_path) {
  json repos = load_repositories(a);
  store::RepositoryConfig c;
  if (auto it = repos.find(name_or_path); it != repos.end()) {
    c.name = name_or_path;
    c.path = it->at("path").get<std::string>();
    for (const auto& k : it->at("keys")) c.trusted_keys.push_back(store::parse_public_key(k.get<std::string>(), "repositories.json: " + name_or_path));
  } else {
    c.name = name_or_path;
    c.path = name_or_path;
  }
  for (const store::PublicKey& k : key_files(a)) c.trusted_keys.push_back(k);
  if (c.trusted_keys.empty()) {
    throw CliError("repository \"" + name_or_path + "\": no trusted key; add it with `marvin skill repo-add NAME PATH --key KEY.pub` or pass --key");
  }
  return c;
}

std::vector<store::Repository> open_repos(const StoreArgs& a) {
  std::vector<std::string> names = a.repos;
  if (names.empty()) {
    json repos = load_repositories(a);
    for (auto it = repos.begin(); it != repos.end(); ++it) names.push_back(it.key());
  }
  if (names.empty()) throw CliError("no repository: pass --repo DIR --key KEY.pub, or add one with `marvin skill repo-add`");
  store::SeenIndexes seen(skills_dir(a) / ".store" / "seen-indexes.json");
  std::vector<store::Repository> out;
  for (const std::string& n : names) out.push_back(store::open_repository(repo_config(a, n), &seen));
  return out;
}

std::string join(const std::vector<std::string>& v) {
  std::string s;
  for (const std::string& x : v) s += (s.empty() ? "" : ", ") + x;
  return s.empty() ? "(none)" : s;
}

std::optional<std::string> sign_password() {
  if (const char* pw = std::getenv("MARVIN_SIGN_PASSWORD")) return std::string(pw);
  return std::nullopt;
}

store::Installer make_installer(const StoreArgs& a) {
  store::InstallOptions o;
  o.assume_yes = a.yes;
  o.allow_downgrade = a.allow_downgrade;
  // What the host would refuse to load is refused before activation (names file and field).
  o.validate = validate_skill_for_host;
  o.approve = [](const store::ApprovalRequest& r) {
    std::cout << r.id << " " << r.version << " asks for these permissions:\n";
    for (const std::string& p : r.permissions) {
      bool added = std::find(r.added_permissions.begin(), r.added_permissions.end(), p) != r.added_permissions.end();
      std::cout << "  - " << p << (added && r.installed_version ? "  (new)" : "") << "\n";
    }
    if (!::isatty(STDIN_FILENO)) {
      std::cout << "not a terminal: pass --yes to approve\n";
      return false;
    }
    std::cout << "Approve? [y/N] " << std::flush;
    std::string answer;
    std::getline(std::cin, answer);
    return answer == "y" || answer == "Y" || answer == "yes";
  };
  return store::Installer(skills_dir(a), o);
}

const char* outcome_text(store::InstallResult::Outcome o) {
  switch (o) {
    case store::InstallResult::Outcome::kInstalled: return "installed";
    case store::InstallResult::Outcome::kUpgraded: return "upgraded";
    case store::InstallResult::Outcome::kDowngraded: return "downgraded";
    case store::InstallResult::Outcome::kAlreadyInstalled: return "already installed";
  }
  return "?";
}

void print_result(const store::InstallResult& r) {
  std::cout << outcome_text(r.outcome) << " " << r.skill.id << " " << r.skill.version;
  if (r.replaced_version) std::cout << " (was " << *r.replaced_version << ")";
  std::cout << "\n";
}

// Installs `id[@version]` from the first repository that has it.
store::InstallResult install_from_repos(const StoreArgs& a, store::Installer& inst, const std::string& spec) {
  std::string id = spec, version;
  if (std::size_t at = spec.find('@'); at != std::string::npos) {
    id = spec.substr(0, at);
    version = spec.substr(at + 1);
  }
  for (const store::Repository& r : open_repos(a)) {
    if (const store::IndexEntry* e = r.index.find(id, version)) {
      store::PackageSource src{r.package_path(*e), {}, r.config.trusted_keys, *e, "repo:" + r.index.name};
      return inst.install(src);
    }
  }
  throw CliError("no repository has " + spec);
}

void install_store_commands(CLI::App& root) {
  CLI::App& skill = command_group(root, "skill", "Skills: make, test, package, install");
  auto args = std::make_shared<StoreArgs>();
  auto common = [args](CLI::App* c) {
    c->add_option("--skills-dir", args->skills_dir, "Installed skills (default $MARVIN_SKILLS_DIR or ~/.local/share/marvin/skills)");
  };
  auto repo_opts = [args](CLI::App* c) {
    c->add_option("--repo", args->repos, "Repository name (see repo-add) or directory");
    c->add_option("--key", args->keys, "Trusted public key file (minisign .pub)");
  };

  CLI::App* pack = skill.add_subcommand("pack", "Build a reproducible .mskill package from a skill folder");
  pack->add_option("DIR", args->target, "Skill folder with skill.json")->required();
  pack->add_option("--sign", args->sign_key, "minisign secret key (unencrypted, or MARVIN_SIGN_PASSWORD)");
  pack->add_option("-o,--output", args->output, "Package file (default <id>-<version>.mskill)");
  pack->callback([args] {
    std::optional<store::SecretKey> key;
    if (!args->sign_key.empty()) key = store::load_secret_key(args->sign_key, sign_password());
    store::PackedSkill p = store::pack_skill(args->target, key ? &*key : nullptr);
    fs::path out = args->output.empty() ? fs::path(p.file_name()) : fs::path(args->output);
    store::write_file_atomic(out, p.archive);
    if (p.signature) store::write_file_atomic(store::signature_path_for(out), *p.signature);
    std::cout << out.string() << " " << p.manifest.id_at_version() << " " << p.digest
              << (p.signature ? " (signed)" : " (unsigned)") << "\n";
  });

  CLI::App* index = skill.add_subcommand("index", "Write and sign a repository's index.json from its packages");
  index->add_option("DIR", args->target, "Repository directory")->required();
  index->add_option("--sign", args->sign_key, "minisign secret key")->required();
  index->add_option("--name", args->name, "Repository name (default: the directory's name)");
  index->add_option("--sequence", args->sequence, "Index sequence (default: previous + 1)");
  index->callback([args] {
    store::SecretKey key = store::load_secret_key(args->sign_key, sign_password());
    std::string name = args->name.empty() ? fs::absolute(args->target).filename().string() : args->name;
    store::RepositoryIndex i = store::build_repository_index(args->target, name, key, args->sequence, key_files(*args));
    std::cout << "index " << i.name << " sequence " << i.sequence << ": " << i.skills.size() << " skills\n";
  });

  CLI::App* repo_add = skill.add_subcommand("repo-add", "Configure a repository and the key it is trusted with");
  repo_add->add_option("NAME", args->name)->required();
  repo_add->add_option("PATH", args->target)->required();
  repo_add->add_option("--key", args->keys, "Trusted public key file")->required();
  common(repo_add);
  repo_add->callback([args] {
    json repos = load_repositories(*args);
    json keys = json::array();
    for (const store::PublicKey& k : key_files(*args)) keys.push_back(k.base64());
    repos[args->name] = {{"path", fs::absolute(args->target).string()}, {"keys", keys}};
    fs::create_directories(repositories_file(*args).parent_path());
    store::write_file_atomic(repositories_file(*args), repos.dump(2) + "\n");
    std::cout << "repository " << args->name << " -> " << fs::absolute(args->target).string() << "\n";
  });

  CLI::App* search = skill.add_subcommand("search", "List the skills of the repositories");
  search->add_option("TERM", args->target, "Part of a skill id");
  common(search);
  repo_opts(search);
  search->callback([args] {
    for (const store::Repository& r : open_repos(*args)) {
      for (const auto& [id, versions] : r.index.skills) {
        if (!args->target.empty() && id.find(args->target) == std::string::npos) continue;
        const store::IndexEntry& e = versions.back();
        std::cout << id << " " << e.version.text << " [" << e.kind << "] from " << r.index.name
                  << " permissions: " << join(e.permissions) << "\n";
      }
    }
  });

  CLI::App* info = skill.add_subcommand("info", "Show a skill's versions and permissions");
  info->add_option("ID", args->target)->required();
  common(info);
  repo_opts(info);
  info->callback([args] {
    store::Installer inst(skills_dir(*args));
    if (auto s = inst.find(args->target)) {
      std::cout << s->id << " installed " << s->version << " (" << s->kind << ", " << s->source << ")"
                << (s->previous ? ", previous " + *s->previous : "") << "\n  permissions: " << join(s->permissions) << "\n";
    }
    if (args->repos.empty() && load_repositories(*args).empty()) return;
    for (const store::Repository& r : open_repos(*args)) {
      auto it = r.index.skills.find(args->target);
      if (it == r.index.skills.end()) continue;
      for (const store::IndexEntry& e : it->second) {
        std::cout << e.id << " " << e.version.text << " in " << r.index.name << ": " << e.kind << ", host API "
                  << e.host_api << ", " << e.size << " bytes, " << e.digest << "\n  permissions: " << join(e.permissions) << "\n";
      }
    }
  });

  auto install_opts = [args](CLI::App* c) {
    c->add_flag("-y,--yes", args->yes, "Approve the permissions without asking");
    c->add_flag("--allow-downgrade", args->allow_downgrade, "Accept a version lower than the installed one");
  };

  CLI::App* install = skill.add_subcommand("install", "Install ID[@VERSION] from a repository, or a .mskill file");
  install->add_option("TARGET", args->target, "Skill id, id@version, or path to a .mskill")->required();
  common(install);
  repo_opts(install);
  install_opts(install);
  install->callback([args] {
    store::Installer inst = make_installer(*args);
    if (args->target.ends_with(".mskill") || fs::is_regular_file(args->target)) {
      std::vector<store::PublicKey> trusted = key_files(*args);
      for (store::PublicKey& k : repository_keys(skills_dir(*args))) trusted.push_back(std::move(k));
      if (trusted.empty()) throw CliError(args->target + ": no trusted key to check its signature; pass --key KEY.pub");
      print_result(inst.install({args->target, {}, trusted, std::nullopt, {}}));
      return;
    }
    print_result(install_from_repos(*args, inst, args->target));
  });

  CLI::App* upgrade = skill.add_subcommand("upgrade", "Upgrade installed skills (or one) to the repositories' latest");
  upgrade->add_option("ID", args->target, "Only this skill");
  common(upgrade);
  repo_opts(upgrade);
  install_opts(upgrade);
  upgrade->callback([args] {
    store::Installer inst = make_installer(*args);
    std::vector<store::Repository> repos = open_repos(*args);
    int upgraded = 0;
    for (const store::InstalledSkill& s : inst.list()) {
      if (!args->target.empty() && s.id != args->target) continue;
      const store::IndexEntry* best = nullptr;
      const store::Repository* from = nullptr;
      for (const store::Repository& r : repos) {
        const store::IndexEntry* e = r.index.find(s.id);
        if (e && (!best || store::compare_versions(e->version, best->version) > 0)) {
          best = e;
          from = &r;
        }
      }
      if (!best || store::compare_versions(best->version, store::parse_version(s.version, "installed")) <= 0) continue;
      print_result(inst.install({from->package_path(*best), {}, from->config.trusted_keys, *best, "repo:" + from->index.name}));
      ++upgraded;
    }
    if (upgraded == 0) std::cout << "everything is up to date\n";
  });

  CLI::App* remove = skill.add_subcommand("remove", "Uninstall a skill (all its versions)");
  remove->add_option("ID", args->target)->required();
  common(remove);
  remove->callback([args] {
    make_installer(*args).remove(args->target);
    std::cout << "removed " << args->target << "\n";
  });

  CLI::App* rollback = skill.add_subcommand("rollback", "Make a skill's previous version current again");
  rollback->add_option("ID", args->target)->required();
  common(rollback);
  rollback->callback([args] {
    store::InstalledSkill s = make_installer(*args).rollback(args->target);
    std::cout << "rolled back " << s.id << " to " << s.version << "\n";
  });

  CLI::App* list = skill.add_subcommand("list", "List installed skills");
  common(list);
  list->callback([args] {
    store::Installer inst(skills_dir(*args));
    std::vector<store::InstalledSkill> all = inst.list();
    if (all.empty()) std::cout << "no skills installed in " << inst.skills_dir().string() << "\n";
    for (const store::InstalledSkill& s : all) {
      std::cout << s.id << " " << s.version << " [" << s.kind << "]"
                << (s.previous ? " (previous " + *s.previous + ")" : "") << " permissions: " << join(s.permissions)
                << " from " << s.source << "\n";
    }
  });
}

}  // namespace

MARVIN_CLI_COMMANDS(install_store_commands);

}  // namespace marvin::app
