#include "store/package.h"

#include <stdexcept>

#include "store/util.h"

namespace marvin::store {

std::string PackedSkill::file_name() const { return manifest.id + "-" + manifest.version.text + ".mskill"; }

PackedSkill pack_skill(const std::filesystem::path& dir, const SecretKey* key) {
  std::filesystem::path manifest_path = dir / "skill.json";
  if (!std::filesystem::is_regular_file(manifest_path)) {
    throw std::runtime_error(manifest_path.string() + ": missing; a skill folder needs its skill.json");
  }
  PackageManifest manifest =
      parse_package_manifest(read_text_file(manifest_path), manifest_path.string());
  std::vector<ArchiveFile> files = collect_directory(dir);
  if (manifest.kind == "native") {
    bool found = false;
    for (const ArchiveFile& f : files) found = found || f.path == manifest.library;
    if (!found) {
      throw std::runtime_error(manifest_path.string() + ": library: \"" + manifest.library +
                               "\" is not in " + dir.string());
    }
  }
  PackedSkill out{.archive = pack_files(std::move(files)), .manifest = manifest, .digest = {}, .signature = {}};
  out.digest = sha256_digest(out.archive);
  if (key != nullptr) {
    out.signature = sign_message(out.archive, *key,
                                 package_trusted_comment(manifest.id_at_version(), out.digest),
                                 "signature of skill package " + out.file_name());
  }
  return out;
}

std::string package_trusted_comment(const std::string& id_at_version, const std::string& digest) {
  return "marvin-skill " + id_at_version + " " + digest;
}

PackageClaim parse_package_trusted_comment(const std::string& comment, const std::string& origin) {
  const std::string prefix = "marvin-skill ";
  auto bad = [&]() {
    return std::runtime_error(origin + ": trusted comment \"" + comment +
                              "\" is not \"marvin-skill <id>@<version> sha256:<digest>\"");
  };
  if (comment.rfind(prefix, 0) != 0) throw bad();
  std::string rest = comment.substr(prefix.size());
  std::size_t space = rest.find(' ');
  if (space == std::string::npos) throw bad();
  std::string who = rest.substr(0, space);
  std::string digest = rest.substr(space + 1);
  std::size_t at = who.find('@');
  if (at == std::string::npos || digest.rfind("sha256:", 0) != 0 || digest.size() != 7 + 64) throw bad();
  return PackageClaim{who.substr(0, at), who.substr(at + 1), digest};
}

PackageClaim verify_package_signature(std::span<const std::uint8_t> package,
                                      const std::string& signature_text,
                                      const std::vector<PublicKey>& trusted,
                                      const std::string& origin) {
  const std::string sig_origin = origin + ".minisig";
  Signature sig = parse_signature(signature_text, sig_origin);
  std::string comment = verify_message(package, sig, trusted, sig_origin);
  PackageClaim claim = parse_package_trusted_comment(comment, sig_origin);
  std::string digest = sha256_digest(package);
  if (claim.digest != digest) {
    throw std::runtime_error(sig_origin + ": trusted comment is for package digest " + claim.digest +
                             ", but " + origin + " has digest " + digest);
  }
  return claim;
}

std::filesystem::path signature_path_for(const std::filesystem::path& package) {
  return package.string() + ".minisig";
}

}  // namespace marvin::store
