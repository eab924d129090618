#include "test_support.h"

#include <archive.h>
#include <archive_entry.h>
#include <elf.h>
#include <sys/sysmacros.h>
#include <sys/wait.h>

#include <cstdlib>
#include <memory>
#include <stdexcept>

#include "store/util.h"

namespace marvin::store::test {

fs::path make_skill_dir(const fs::path& parent, const std::string& id, const std::string& version,
                        const std::vector<std::string>& permissions, const std::string& host_api,
                        const std::string& extra_file) {
  fs::path dir = parent / (id + "-" + version + "-src");
  std::string perms;
  for (const std::string& p : permissions) perms += (perms.empty() ? "\"" : ", \"") + p + "\"";
  write_text(dir / "skill.json", "{\"id\": \"" + id + "\", \"version\": \"" + version +
                                     "\", \"kind\": \"lua\", \"host_api\": \"" + host_api +
                                     "\", \"permissions\": [" + perms + "]}\n");
  write_text(dir / "main.lua", "-- " + id + " " + version + "\nmarvin.say('hi')\n");
  write_text(dir / "lib/util.lua", "return {version = '" + version + "'}\n");
  if (!extra_file.empty()) write_text(dir / extra_file, "extra " + version + "\n");
  return dir;
}

Bytes fake_elf_so(std::uint16_t machine) {
  Bytes b(64, 0);
  b[0] = 0x7f; b[1] = 'E'; b[2] = 'L'; b[3] = 'F';
  b[EI_CLASS] = ELFCLASS64;
  b[EI_DATA] = ELFDATA2LSB;
  b[EI_VERSION] = EV_CURRENT;
  b[16] = ET_DYN;
  b[18] = static_cast<std::uint8_t>(machine & 0xff);
  b[19] = static_cast<std::uint8_t>(machine >> 8);
  return b;
}

Bytes raw_archive(const std::vector<RawEntry>& entries) {
  std::unique_ptr<archive, decltype(&archive_write_free)> a(archive_write_new(), archive_write_free);
  archive_write_set_format_pax_restricted(a.get());
  archive_write_add_filter_gzip(a.get());
  archive_write_set_bytes_in_last_block(a.get(), 1);
  Bytes out;
  auto cb = [](archive*, void* client, const void* buf, std::size_t len) -> la_ssize_t {
    auto* o = static_cast<Bytes*>(client);
    const auto* p = static_cast<const std::uint8_t*>(buf);
    o->insert(o->end(), p, p + len);
    return static_cast<la_ssize_t>(len);
  };
  archive_write_open(a.get(), &out, nullptr, cb, nullptr);
  for (const RawEntry& r : entries) {
    std::unique_ptr<archive_entry, decltype(&archive_entry_free)> e(archive_entry_new(), archive_entry_free);
    archive_entry_set_pathname(e.get(), r.path.c_str());
    archive_entry_set_filetype(e.get(), r.type);
    archive_entry_set_perm(e.get(), 0644);
    if (r.type == AE_IFLNK) archive_entry_set_symlink(e.get(), r.link.c_str());
    if (r.type == AE_IFREG && !r.link.empty()) archive_entry_set_hardlink(e.get(), r.link.c_str());
    if (r.type == AE_IFCHR) archive_entry_set_rdev(e.get(), makedev(1, 3));
    archive_entry_set_size(e.get(), r.type == AE_IFREG && r.link.empty() ? static_cast<la_int64_t>(r.content.size()) : 0);
    if (archive_write_header(a.get(), e.get()) != ARCHIVE_OK) {
      throw std::runtime_error(std::string("raw_archive: ") + archive_error_string(a.get()));
    }
    if (r.type == AE_IFREG && r.link.empty() && !r.content.empty()) {
      archive_write_data(a.get(), r.content.data(), r.content.size());
    }
  }
  archive_write_close(a.get());
  return out;
}

fs::path write_signed(const fs::path& dir, const std::string& name, const Bytes& bytes,
                      const SecretKey& key, const std::string& id_at_version) {
  fs::path p = dir / name;
  write_file_atomic(p, bytes);
  write_file_atomic(signature_path_for(p),
                    sign_message(bytes, key, package_trusted_comment(id_at_version, sha256_digest(bytes))));
  return p;
}

std::map<std::string, std::string> package_files(const fs::path& package) {
  std::map<std::string, std::string> out;
  for (auto& [path, bytes] : read_archive(read_file(package), ArchiveLimits{}, package.string())) {
    out[path] = std::string(bytes.begin(), bytes.end());
  }
  return out;
}

int run(const std::string& command) {
  int status = std::system(command.c_str());
  if (status == -1 || !WIFEXITED(status)) return -1;
  return WEXITSTATUS(status);
}

}  // namespace marvin::store::test
