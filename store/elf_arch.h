// The CPU architecture of a native skill's shared library, read from its ELF header, and
// the host's, so a package built for another CPU is refused before anything dlopen()s it.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>

namespace marvin::store {

struct ElfArch {
  std::uint16_t machine = 0;  // e_machine (EM_X86_64, EM_AARCH64, EM_ARM, ...)
  std::uint8_t elf_class = 0; // 1 = 32-bit, 2 = 64-bit
  std::uint8_t data = 0;      // 1 = little-endian, 2 = big-endian
  bool operator==(const ElfArch&) const = default;
  // "x86_64", "aarch64", "arm", "i386", "riscv64" ... or "machine 0x.." with class and
  // byte order.
  std::string name() const;
};

// Reads the ELF identification of `bytes` (at least the 64-byte header). Throws naming
// `origin` when it is not an ELF shared object.
ElfArch read_elf_arch(std::span<const std::uint8_t> bytes, const std::string& origin);
ElfArch read_elf_arch(const std::filesystem::path& file);

// The architecture this program was built for.
ElfArch host_elf_arch();

}  // namespace marvin::store
