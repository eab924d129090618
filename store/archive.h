// The archive inside a .mskill package: a gzip-compressed tar, written reproducibly and
// read defensively.
//
// Packing: regular files only, sorted by path (byte order), every entry with mode 0644,
// owner 0:0 and no owner names, mtime kMTime, pax-restricted tar, gzip without a time
// stamp, no block padding. The same files give the same bytes, whatever the clock, the
// umask, the file system order or the user who packs.
//
// Reading: each entry is checked before any byte is written, and the archive is refused
// with a message naming the entry for: absolute paths, "..", "." or empty path
// components, backslashes or control characters, symbolic and hard links, device files,
// FIFOs, sockets, sparse files, duplicate entries (or a file that is also a directory),
// more than ArchiveLimits::max_entries entries, more than max_total_bytes bytes after
// decompression (counted while reading, not trusted from headers), truncated or corrupted
// data (libarchive's message is included; the gzip CRC-32 and length, which libarchive does
// not check, are checked too, so the package must be exactly one gzip member).
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "store/util.h"

namespace marvin::store {

struct ArchiveLimits {
  std::size_t max_entries = 4096;                 // files + directories
  std::uint64_t max_total_bytes = 64ull << 20;    // decompressed file content
  std::size_t max_path_bytes = 512;
};

struct ArchiveFile {
  std::string path;  // relative, '/'-separated
  Bytes content;
};

inline constexpr std::int64_t kPackedMTime = 946684800;  // 2000-01-01T00:00:00Z

// Packs `files` (any order; sorted here) into archive bytes. Throws on a bad or duplicate path.
Bytes pack_files(std::vector<ArchiveFile> files);

// Reads every regular file under `dir` (hidden files and directories, starting with '.',
// are skipped). Throws naming the path on a symlink, device or other special file.
std::vector<ArchiveFile> collect_directory(const std::filesystem::path& dir);

// Called before each entry is written during extraction ("extract <path>"); the installer's
// crash-injection hook for tests.
using StepHook = std::function<void(std::string_view step)>;

// Extracts `archive` into the existing empty directory `dest` under the checks above.
// `origin` (the package file name) starts every message. With `durable`, every file and
// directory is fsync'ed. Returns the extracted file paths, sorted. On error `dest` may
// hold part of the files: the caller owns and removes it.
std::vector<std::string> extract_archive(std::span<const std::uint8_t> archive,
                                         const std::filesystem::path& dest,
                                         const ArchiveLimits& limits, const std::string& origin,
                                         bool durable = true, const StepHook& hook = {});

// Reads the regular files of `archive` into memory under the same checks.
std::map<std::string, Bytes> read_archive(std::span<const std::uint8_t> archive,
                                          const ArchiveLimits& limits, const std::string& origin);

}  // namespace marvin::store
