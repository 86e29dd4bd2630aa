#include "plugin/elf_check.hpp"

#include "facet/plugin.hpp"

#include <elf.h>

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstring>
#include <fstream>

namespace facet {

namespace fs = std::filesystem;

namespace {

#if defined(__x86_64__)
constexpr uint16_t kHostMachine = EM_X86_64;
#elif defined(__aarch64__)
constexpr uint16_t kHostMachine = EM_AARCH64;
#elif defined(__riscv) && __riscv_xlen == 64
constexpr uint16_t kHostMachine = EM_RISCV;
#else
constexpr uint16_t kHostMachine = EM_NONE;  // not checked
#endif

const char* machine_name(uint16_t machine) {
    switch (machine) {
        case EM_X86_64: return "x86-64";
        case EM_386: return "32-bit x86";
        case EM_AARCH64: return "AArch64";
        case EM_ARM: return "32-bit ARM";
        case EM_RISCV: return "RISC-V";
        case EM_PPC64: return "64-bit PowerPC";
        case EM_S390: return "s390";
        default: return "another machine";
    }
}

bool native_byte_order(const Elf64_Ehdr& eh) {
    return eh.e_ident[EI_DATA] ==
           (std::endian::native == std::endian::little ? ELFDATA2LSB : ELFDATA2MSB);
}

}  // namespace

std::optional<std::string> elf_incomplete(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    Elf64_Ehdr eh{};
    std::error_code ec;
    const uint64_t size = fs::file_size(path, ec);
    if (ec) return "cannot read it: " + ec.message();
    if (!in.read(reinterpret_cast<char*>(&eh), sizeof eh) ||
        std::memcmp(eh.e_ident, ELFMAG, SELFMAG) != 0 || eh.e_ident[EI_CLASS] != ELFCLASS64)
        return "not a 64-bit ELF shared library";
    // The offsets below are in the file's byte order: one of the other
    // order is whole as far as this can tell, and elf_foreign names it.
    if (!native_byte_order(eh)) return std::nullopt;
    uint64_t needed = uint64_t(eh.e_shoff) + uint64_t(eh.e_shnum) * eh.e_shentsize;
    needed = std::max<uint64_t>(needed, eh.e_phoff + uint64_t(eh.e_phnum) * eh.e_phentsize);
    for (int i = 0; i < eh.e_phnum && needed <= size; ++i) {
        Elf64_Phdr ph{};
        in.seekg(std::streamoff(eh.e_phoff + uint64_t(i) * eh.e_phentsize));
        if (!in.read(reinterpret_cast<char*>(&ph), sizeof ph)) break;
        if (ph.p_type == PT_LOAD) needed = std::max<uint64_t>(needed, ph.p_offset + ph.p_filesz);
    }
    if (needed > size)
        return "file is truncated (" + std::to_string(size) + " bytes, its headers need " +
               std::to_string(needed) + "); is it still being written?";
    return std::nullopt;
}

std::optional<std::string> elf_foreign(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    Elf64_Ehdr eh{};
    if (!in.read(reinterpret_cast<char*>(&eh), sizeof eh)) return std::nullopt;
    if (!native_byte_order(eh)) return std::string("built for a machine of the other byte order");
    // e_type and e_machine are in the file's byte order, which is ours.
    if (kHostMachine != EM_NONE && eh.e_machine != kHostMachine)
        return std::string("built for ") + machine_name(eh.e_machine) + " (ELF machine " +
               std::to_string(eh.e_machine) + "), and this process runs on " +
               machine_name(kHostMachine) + ": build it for this machine";
    if (eh.e_type == ET_REL)
        return std::string("an object file, not a shared library: link it with -shared "
                           "(facet_add_shader() in CMake does)");
    if (eh.e_type != ET_DYN) return std::string("not a shared library (ELF type ") +
                                    std::to_string(eh.e_type) + ")";
    return std::nullopt;
}

bool plugin_file_complete(const fs::path& path) { return !elf_incomplete(path); }

}  // namespace facet
