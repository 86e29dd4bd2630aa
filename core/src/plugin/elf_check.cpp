#include "plugin/elf_check.hpp"

#include "facet/plugin.hpp"

#include <elf.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <fstream>

namespace facet {

namespace fs = std::filesystem;

std::optional<std::string> elf_incomplete(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    Elf64_Ehdr eh{};
    std::error_code ec;
    const uint64_t size = fs::file_size(path, ec);
    if (ec) return "cannot read it: " + ec.message();
    if (!in.read(reinterpret_cast<char*>(&eh), sizeof eh) ||
        std::memcmp(eh.e_ident, ELFMAG, SELFMAG) != 0 || eh.e_ident[EI_CLASS] != ELFCLASS64)
        return "not a 64-bit ELF shared library";
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

bool plugin_file_complete(const fs::path& path) { return !elf_incomplete(path); }

}  // namespace facet
