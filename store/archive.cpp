#include "store/archive.h"

#include <archive.h>
#include <archive_entry.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstring>
#include <memory>
#include <set>
#include <stdexcept>

namespace marvin::store {
namespace {

struct ArchiveWriteDeleter {
  void operator()(archive* a) const { archive_write_free(a); }
};
struct ArchiveReadDeleter {
  void operator()(archive* a) const { archive_read_free(a); }
};
struct EntryDeleter {
  void operator()(archive_entry* e) const { archive_entry_free(e); }
};

std::string entry_name(std::string_view s) {
  std::string out = "'";
  for (char c : s) {
    auto u = static_cast<unsigned char>(c);
    if (u < 0x20 || u == 0x7f) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\x%02x", u);
      out += buf;
    } else {
      out += c;
    }
  }
  return out + "'";
}

// Why `path` is not a safe relative path, or "" when it is.
std::string path_problem(std::string_view path, std::size_t max_bytes) {
  if (path.empty()) return "has an empty name";
  if (path.size() > max_bytes) return "has a name longer than " + std::to_string(max_bytes) + " bytes";
  if (path.front() == '/') return "has an absolute path";
  for (char c : path) {
    auto u = static_cast<unsigned char>(c);
    if (u < 0x20 || u == 0x7f) return "has a control character in its name";
    if (c == '\\') return "has a backslash in its name";
  }
  std::size_t start = 0;
  while (start <= path.size()) {
    std::size_t end = path.find('/', start);
    if (end == std::string_view::npos) end = path.size();
    std::string_view comp = path.substr(start, end - start);
    if (comp == "..") return "escapes the package (path traversal with \"..\")";
    if (comp == ".") return "has a \".\" path component";
    if (comp.empty()) return "has an empty path component";
    if (comp.size() > 255) return "has a path component longer than 255 bytes";
    start = end + 1;
  }
  return "";
}

std::uint32_t crc32_update(std::uint32_t crc, const std::uint8_t* p, std::size_t n) {
  static const auto table = [] {
    std::array<std::uint32_t, 256> t{};
    for (std::uint32_t i = 0; i < 256; ++i) {
      std::uint32_t c = i;
      for (int k = 0; k < 8; ++k) c = (c & 1) ? 0xedb88320u ^ (c >> 1) : c >> 1;
      t[i] = c;
    }
    return t;
  }();
  crc = ~crc;
  for (std::size_t i = 0; i < n; ++i) crc = table[(crc ^ p[i]) & 0xff] ^ (crc >> 8);
  return ~crc;
}

// libarchive's gzip reader does not check the gzip trailer (CRC-32 and length), so damaged
// compressed data can decode into other bytes without an error. Decompress the whole
// stream once more and compare with the trailer, which must be the last 8 bytes: a package
// is exactly one gzip member with nothing after it (as pack_files writes it); block
// padding or trailing bytes are refused like corruption.
void check_gzip_trailer(std::span<const std::uint8_t> bytes, std::uint64_t limit, const std::string& origin,
                        const std::string& last_entry) {
  const std::string where = origin + ": corrupted archive (after entry " + last_entry + "): ";
  if (bytes.size() < 18) throw std::runtime_error(where + "too short for gzip");
  std::unique_ptr<archive, ArchiveReadDeleter> a(archive_read_new());
  archive_read_support_filter_gzip(a.get());
  archive_read_support_format_raw(a.get());
  archive_entry* e = nullptr;
  if (archive_read_open_memory(a.get(), bytes.data(), bytes.size()) != ARCHIVE_OK ||
      archive_read_next_header(a.get(), &e) != ARCHIVE_OK) {
    throw std::runtime_error(where + archive_error_string(a.get()));
  }
  std::vector<std::uint8_t> buf(64 * 1024);
  std::uint32_t crc = 0;
  std::uint64_t total = 0;
  while (true) {
    la_ssize_t n = archive_read_data(a.get(), buf.data(), buf.size());
    if (n == 0) break;
    if (n < 0) throw std::runtime_error(where + archive_error_string(a.get()));
    crc = crc32_update(crc, buf.data(), static_cast<std::size_t>(n));
    total += static_cast<std::uint64_t>(n);
    if (total > limit) throw std::runtime_error(where + "more than " + std::to_string(limit) + " bytes after decompression");
  }
  const std::uint8_t* t = bytes.data() + bytes.size() - 8;
  std::uint32_t want_crc = static_cast<std::uint32_t>(t[0] | (t[1] << 8) | (t[2] << 16)) | (static_cast<std::uint32_t>(t[3]) << 24);
  std::uint32_t want_len = static_cast<std::uint32_t>(t[4] | (t[5] << 8) | (t[6] << 16)) | (static_cast<std::uint32_t>(t[7]) << 24);
  if (crc != want_crc || static_cast<std::uint32_t>(total) != want_len) {
    throw std::runtime_error(where + "the data does not match the gzip checksum (CRC-32/length), or bytes follow the gzip stream");
  }
}

struct EntrySink {
  virtual ~EntrySink() = default;
  virtual void directory(const std::string& path) = 0;
  virtual void begin_file(const std::string& path) = 0;
  virtual void write(const void* data, std::size_t size) = 0;
  virtual void end_file() = 0;
};

void read_entries(std::span<const std::uint8_t> bytes, const ArchiveLimits& limits,
                  const std::string& origin, EntrySink& sink) {
  std::unique_ptr<archive, ArchiveReadDeleter> a(archive_read_new());
  if (!a) throw std::runtime_error(origin + ": out of memory");
  archive_read_support_filter_gzip(a.get());
  archive_read_support_format_tar(a.get());
  if (bytes.empty()) throw std::runtime_error(origin + ": corrupted archive: the package is empty");
  if (archive_read_open_memory(a.get(), bytes.data(), bytes.size()) != ARCHIVE_OK) {
    throw std::runtime_error(origin + ": corrupted archive (not a gzip-compressed tar): " +
                             archive_error_string(a.get()));
  }
  std::set<std::string> files, dirs;
  std::size_t entries = 0;
  std::uint64_t total = 0;
  std::string previous = "(start of archive)";
  std::vector<char> buf(64 * 1024);
  while (true) {
    archive_entry* e = nullptr;
    int rc = archive_read_next_header(a.get(), &e);
    if (rc == ARCHIVE_EOF) break;
    if (rc != ARCHIVE_OK) {
      const char* msg = archive_error_string(a.get());
      throw std::runtime_error(origin + ": corrupted or truncated archive after entry " + previous +
                               ": " + (msg ? msg : "unknown error"));
    }
    ++entries;
    const char* raw_name = archive_entry_pathname(e);
    std::string name = raw_name ? raw_name : "";
    if (entries > limits.max_entries) {
      throw std::runtime_error(origin + ": too many entries: entry " + entry_name(name) + " is number " +
                               std::to_string(entries) + ", the limit is " +
                               std::to_string(limits.max_entries));
    }
    std::string where = origin + ": entry " + entry_name(name) + " ";
    if (const char* target = archive_entry_hardlink(e)) {
      throw std::runtime_error(where + "is a hard link (to " + entry_name(target) + "); links are not allowed");
    }
    mode_t type = archive_entry_filetype(e);
    if (type == AE_IFLNK) {
      const char* target = archive_entry_symlink(e);
      throw std::runtime_error(where + "is a symbolic link (to " + entry_name(target ? target : "") +
                               "); links are not allowed");
    }
    if (type == AE_IFCHR || type == AE_IFBLK) throw std::runtime_error(where + "is a device file");
    if (type == AE_IFIFO) throw std::runtime_error(where + "is a FIFO (named pipe)");
    if (type == AE_IFSOCK) throw std::runtime_error(where + "is a socket");
    if (type != AE_IFREG && type != AE_IFDIR) throw std::runtime_error(where + "has an unsupported file type");
    if (archive_entry_sparse_count(e) > 0) throw std::runtime_error(where + "is a sparse file");
    std::string path = name;
    if (type == AE_IFDIR && !path.empty() && path.back() == '/') path.pop_back();
    if (std::string problem = path_problem(path, limits.max_path_bytes); !problem.empty()) {
      throw std::runtime_error(where + problem);
    }
    // A parent of this entry must not be a file.
    for (std::size_t slash = path.find('/'); slash != std::string::npos; slash = path.find('/', slash + 1)) {
      std::string parent = path.substr(0, slash);
      if (files.count(parent)) {
        throw std::runtime_error(where + "is inside " + entry_name(parent) + ", which is a file");
      }
    }
    if (files.count(path) || (type == AE_IFREG && dirs.count(path))) {
      throw std::runtime_error(where + "is a duplicate entry");
    }
    for (std::size_t slash = path.find('/'); slash != std::string::npos; slash = path.find('/', slash + 1)) {
      dirs.insert(path.substr(0, slash));
    }
    previous = entry_name(name);
    if (type == AE_IFDIR) {
      if (!dirs.insert(path).second) continue;  // the same directory twice is harmless
      sink.directory(path);
      continue;
    }
    files.insert(path);
    if (archive_entry_size_is_set(e) && archive_entry_size(e) > 0 &&
        total + static_cast<std::uint64_t>(archive_entry_size(e)) > limits.max_total_bytes) {
      throw std::runtime_error(where + "makes the package larger than " +
                               std::to_string(limits.max_total_bytes) +
                               " bytes after decompression (declared size " +
                               std::to_string(archive_entry_size(e)) + ")");
    }
    sink.begin_file(path);
    while (true) {
      la_ssize_t n = archive_read_data(a.get(), buf.data(), buf.size());
      if (n == 0) break;
      if (n < 0) {
        const char* msg = archive_error_string(a.get());
        throw std::runtime_error(where + "is corrupted or truncated: " + (msg ? msg : "read error"));
      }
      total += static_cast<std::uint64_t>(n);
      if (total > limits.max_total_bytes) {
        throw std::runtime_error(where + "makes the package larger than " +
                                 std::to_string(limits.max_total_bytes) + " bytes after decompression");
      }
      sink.write(buf.data(), static_cast<std::size_t>(n));
    }
    sink.end_file();
  }
  // Tar headers and padding add at most 1.5 KB per entry (pax header + ustar header +
  // padding) on top of the content, plus the end-of-archive blocks.
  check_gzip_trailer(bytes, limits.max_total_bytes + 2048 * (entries + 2), origin, previous);
}

class DirectorySink : public EntrySink {
 public:
  DirectorySink(std::filesystem::path dest, bool durable, const StepHook& hook)
      : dest_(std::move(dest)), durable_(durable), hook_(hook) {}
  ~DirectorySink() override {
    if (fd_ >= 0) ::close(fd_);
  }

  void directory(const std::string& path) override { make_dirs(path); }

  void begin_file(const std::string& path) override {
    if (hook_) hook_("extract " + path);
    std::size_t slash = path.rfind('/');
    if (slash != std::string::npos) make_dirs(path.substr(0, slash));
    current_ = dest_ / path;
    fd_ = ::open(current_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644);
    if (fd_ < 0) throw std::runtime_error(current_.string() + ": cannot create: " + std::strerror(errno));
    written_.push_back(path);
  }

  void write(const void* data, std::size_t size) override {
    const char* p = static_cast<const char*>(data);
    while (size > 0) {
      ssize_t n = ::write(fd_, p, size);
      if (n < 0 && errno == EINTR) continue;
      if (n < 0) throw std::runtime_error(current_.string() + ": write failed: " + std::strerror(errno));
      p += n;
      size -= static_cast<std::size_t>(n);
    }
  }

  void end_file() override {
    if (durable_ && ::fsync(fd_) != 0) {
      throw std::runtime_error(current_.string() + ": fsync failed: " + std::strerror(errno));
    }
    ::close(fd_);
    fd_ = -1;
  }

  void finish() {
    if (!durable_) return;
    for (const std::string& d : made_dirs_) sync_path(dest_ / d);
    sync_path(dest_);
  }

  std::vector<std::string> written() {
    std::sort(written_.begin(), written_.end());
    return written_;
  }

 private:
  void make_dirs(const std::string& rel) {
    std::size_t pos = 0;
    while (pos != std::string::npos) {
      pos = rel.find('/', pos + 1);
      std::string part = rel.substr(0, pos);
      std::filesystem::path full = dest_ / part;
      if (::mkdir(full.c_str(), 0755) == 0) {
        made_dirs_.push_back(part);
      } else if (errno != EEXIST) {
        throw std::runtime_error(full.string() + ": cannot create directory: " + std::strerror(errno));
      }
    }
  }

  std::filesystem::path dest_;
  bool durable_;
  const StepHook& hook_;
  std::filesystem::path current_;
  int fd_ = -1;
  std::vector<std::string> written_;
  std::vector<std::string> made_dirs_;
};

class MemorySink : public EntrySink {
 public:
  void directory(const std::string&) override {}
  void begin_file(const std::string& path) override { current_ = &files[path]; }
  void write(const void* data, std::size_t size) override {
    const auto* p = static_cast<const std::uint8_t*>(data);
    current_->insert(current_->end(), p, p + size);
  }
  void end_file() override { current_ = nullptr; }
  std::map<std::string, Bytes> files;

 private:
  Bytes* current_ = nullptr;
};

}  // namespace

Bytes pack_files(std::vector<ArchiveFile> files) {
  std::sort(files.begin(), files.end(),
            [](const ArchiveFile& a, const ArchiveFile& b) { return a.path < b.path; });
  ArchiveLimits limits;
  std::set<std::string> seen;
  for (const ArchiveFile& f : files) {
    if (std::string problem = path_problem(f.path, limits.max_path_bytes); !problem.empty()) {
      throw std::runtime_error("pack: file " + entry_name(f.path) + " " + problem);
    }
    if (!seen.insert(f.path).second) throw std::runtime_error("pack: file " + entry_name(f.path) + " appears twice");
  }
  std::unique_ptr<archive, ArchiveWriteDeleter> a(archive_write_new());
  archive_write_set_format_pax_restricted(a.get());
  archive_write_add_filter_gzip(a.get());
  // No time stamp in the gzip header; maximum compression is deterministic too.
  archive_write_set_filter_option(a.get(), "gzip", "timestamp", nullptr);
  archive_write_set_filter_option(a.get(), "gzip", "compression-level", "9");
  archive_write_set_bytes_per_block(a.get(), 512);
  archive_write_set_bytes_in_last_block(a.get(), 1);
  // The output size is not known up front: libarchive's memory writer needs a buffer, so
  // write through a callback into a vector instead.
  Bytes out;
  auto write_cb = [](archive*, void* client, const void* buffer, std::size_t length) -> la_ssize_t {
    auto* o = static_cast<Bytes*>(client);
    const auto* p = static_cast<const std::uint8_t*>(buffer);
    o->insert(o->end(), p, p + length);
    return static_cast<la_ssize_t>(length);
  };
  if (archive_write_open(a.get(), &out, nullptr, write_cb, nullptr) != ARCHIVE_OK) {
    throw std::runtime_error(std::string("pack: cannot start archive: ") + archive_error_string(a.get()));
  }
  for (const ArchiveFile& f : files) {
    std::unique_ptr<archive_entry, EntryDeleter> e(archive_entry_new());
    archive_entry_set_pathname(e.get(), f.path.c_str());
    archive_entry_set_filetype(e.get(), AE_IFREG);
    archive_entry_set_perm(e.get(), 0644);
    archive_entry_set_uid(e.get(), 0);
    archive_entry_set_gid(e.get(), 0);
    archive_entry_set_mtime(e.get(), kPackedMTime, 0);
    archive_entry_set_size(e.get(), static_cast<la_int64_t>(f.content.size()));
    if (archive_write_header(a.get(), e.get()) != ARCHIVE_OK) {
      throw std::runtime_error("pack: file " + entry_name(f.path) + ": " + archive_error_string(a.get()));
    }
    if (!f.content.empty() &&
        archive_write_data(a.get(), f.content.data(), f.content.size()) !=
            static_cast<la_ssize_t>(f.content.size())) {
      throw std::runtime_error("pack: file " + entry_name(f.path) + ": " + archive_error_string(a.get()));
    }
  }
  if (archive_write_close(a.get()) != ARCHIVE_OK) {
    throw std::runtime_error(std::string("pack: cannot finish archive: ") + archive_error_string(a.get()));
  }
  return out;
}

std::vector<ArchiveFile> collect_directory(const std::filesystem::path& dir) {
  namespace fs = std::filesystem;
  if (!fs::is_directory(dir)) throw std::runtime_error(dir.string() + ": not a directory");
  std::vector<ArchiveFile> files;
  for (auto it = fs::recursive_directory_iterator(dir); it != fs::recursive_directory_iterator(); ++it) {
    const fs::path& p = it->path();
    std::string rel = fs::relative(p, dir).generic_string();
    if (p.filename().string().front() == '.') {
      if (it->is_directory(/*follow*/)) it.disable_recursion_pending();
      continue;
    }
    fs::file_status st = it->symlink_status();
    if (fs::is_symlink(st)) throw std::runtime_error(p.string() + ": symbolic links cannot be packed");
    if (fs::is_directory(st)) continue;
    if (!fs::is_regular_file(st)) throw std::runtime_error(p.string() + ": not a regular file; cannot be packed");
    files.push_back({rel, read_file(p)});
  }
  return files;
}

std::vector<std::string> extract_archive(std::span<const std::uint8_t> archive_bytes,
                                         const std::filesystem::path& dest,
                                         const ArchiveLimits& limits, const std::string& origin,
                                         bool durable, const StepHook& hook) {
  DirectorySink sink(dest, durable, hook);
  read_entries(archive_bytes, limits, origin, sink);
  sink.finish();
  return sink.written();
}

std::map<std::string, Bytes> read_archive(std::span<const std::uint8_t> archive_bytes,
                                          const ArchiveLimits& limits, const std::string& origin) {
  MemorySink sink;
  read_entries(archive_bytes, limits, origin, sink);
  return std::move(sink.files);
}

}  // namespace marvin::store
