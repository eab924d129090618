// Small file and encoding helpers shared by the store: whole-file reads, durable atomic
// writes, hex, SHA-256 digests. Every function throws std::runtime_error naming the file.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace marvin::store {

using Bytes = std::vector<std::uint8_t>;

// The whole file. Throws if it cannot be opened or is larger than `max_bytes`.
Bytes read_file(const std::filesystem::path& path, std::uint64_t max_bytes = 1ull << 30);
std::string read_text_file(const std::filesystem::path& path,
                           std::uint64_t max_bytes = 64ull << 20);

// Writes `data` to `path` so that after return the file holds either its old content or
// the new one, even across a crash or power cut: a temporary file in the same directory,
// fsync, rename over `path`, fsync of the directory.
void write_file_atomic(const std::filesystem::path& path, std::span<const std::uint8_t> data);
void write_file_atomic(const std::filesystem::path& path, std::string_view text);

// fsync of a file or directory (directories make renames and creations durable).
void sync_path(const std::filesystem::path& path);

std::string to_hex(std::span<const std::uint8_t> bytes);

// "sha256:<64 hex digits>" of the bytes: the package digest used by indexes, signatures
// and the lock file.
std::string sha256_digest(std::span<const std::uint8_t> bytes);

// Ensures libsodium is initialised (idempotent, thread-safe).
void init_sodium();

}  // namespace marvin::store
