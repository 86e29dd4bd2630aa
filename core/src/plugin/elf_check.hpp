// Whether a file is a whole ELF-64 shared library, before dlopen() maps it.
//
// dlopen() maps a library's segments straight from the file; a segment that
// runs past the end of a truncated file (a compiler still writing it) faults
// with SIGBUS on first touch. The loader and hot reload (which waits for a
// plugin's build to finish) ask here first.
//
// Takes: a path. Gives: why it is not a whole ELF-64 file, or why a whole
// one cannot be loaded here (another machine or byte order, an object file
// or an executable), or nothing.
#pragma once

#include <filesystem>
#include <optional>
#include <string>

namespace facet {

std::optional<std::string> elf_incomplete(const std::filesystem::path& path);
// Of a whole ELF-64 file (elf_incomplete gave nothing).
std::optional<std::string> elf_foreign(const std::filesystem::path& path);

}  // namespace facet
