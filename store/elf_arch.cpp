#include "store/elf_arch.h"

#include <elf.h>

#include <cstdio>
#include <fstream>
#include <stdexcept>
#include <vector>

namespace marvin::store {

std::string ElfArch::name() const {
  std::string base;
  switch (machine) {
    case EM_X86_64: base = elf_class == ELFCLASS64 ? "x86_64" : "x32"; break;
    case EM_386: base = "i386"; break;
    case EM_AARCH64: base = "aarch64"; break;
    case EM_ARM: base = "arm"; break;
    case EM_RISCV: base = elf_class == ELFCLASS64 ? "riscv64" : "riscv32"; break;
    case EM_PPC64: base = "ppc64"; break;
    case EM_S390: base = "s390x"; break;
    default: {
      char buf[32];
      std::snprintf(buf, sizeof buf, "machine 0x%04x", machine);
      base = buf;
    }
  }
  base += elf_class == ELFCLASS64 ? " (64-bit" : " (32-bit";
  base += data == ELFDATA2LSB ? ", little-endian)" : ", big-endian)";
  return base;
}

ElfArch read_elf_arch(std::span<const std::uint8_t> b, const std::string& origin) {
  if (b.size() < 20 || b[0] != 0x7f || b[1] != 'E' || b[2] != 'L' || b[3] != 'F') {
    throw std::runtime_error(origin + ": not an ELF file (bad magic)");
  }
  ElfArch a;
  a.elf_class = b[EI_CLASS];
  a.data = b[EI_DATA];
  if ((a.elf_class != ELFCLASS32 && a.elf_class != ELFCLASS64) ||
      (a.data != ELFDATA2LSB && a.data != ELFDATA2MSB)) {
    throw std::runtime_error(origin + ": ELF header has an unknown class or byte order");
  }
  // e_type at 16, e_machine at 18, in the file's byte order.
  auto u16 = [&](std::size_t off) {
    return a.data == ELFDATA2LSB ? static_cast<std::uint16_t>(b[off] | (b[off + 1] << 8))
                                 : static_cast<std::uint16_t>((b[off] << 8) | b[off + 1]);
  };
  if (u16(16) != ET_DYN) throw std::runtime_error(origin + ": ELF file is not a shared object (e_type is not ET_DYN)");
  a.machine = u16(18);
  return a;
}

ElfArch read_elf_arch(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::vector<std::uint8_t> head(64);
  in.read(reinterpret_cast<char*>(head.data()), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<std::size_t>(in.gcount()));
  return read_elf_arch(head, file.string());
}

ElfArch host_elf_arch() {
  ElfArch a;
#if defined(__x86_64__) && defined(__LP64__)
  a.machine = EM_X86_64;
#elif defined(__x86_64__)
  a.machine = EM_X86_64;
#elif defined(__i386__)
  a.machine = EM_386;
#elif defined(__aarch64__)
  a.machine = EM_AARCH64;
#elif defined(__arm__)
  a.machine = EM_ARM;
#elif defined(__riscv)
  a.machine = EM_RISCV;
#elif defined(__powerpc64__)
  a.machine = EM_PPC64;
#elif defined(__s390x__)
  a.machine = EM_S390;
#else
#error "host_elf_arch: unknown CPU; add its EM_ constant"
#endif
  a.elf_class = sizeof(void*) == 8 ? ELFCLASS64 : ELFCLASS32;
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_BIG_ENDIAN__
  a.data = ELFDATA2MSB;
#else
  a.data = ELFDATA2LSB;
#endif
  return a;
}

}  // namespace marvin::store
