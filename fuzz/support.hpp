// What the fuzz targets share (private to fuzz/): failing with a message,
// a private folder to write inputs into, and the build's shader plugins.
#pragma once

#include "fuzz.hpp"

#include <facet/material.hpp>
#include <facet/plugin.hpp>

#include <cstddef>
#include <cstdint>
#include <exception>
#include <filesystem>
#include <string>
#include <string_view>

namespace facet::fuzz {

[[noreturn]] void fail(const std::string& what);
inline void check(bool ok, std::string_view what) {
    if (!ok) fail(std::string(what));
}

// An exception's dynamic type and message, for "threw X" failures.
std::string describe(const std::exception& e);

// Fails: `call` threw `e`, which is not a facet::Error.
[[noreturn]] void unexpected(const std::string& call, const std::exception& e);

// A folder of this process's own, laid out like the repository so that the
// relative paths in its scenes and materials resolve:
//
//   configs/materials/*.yaml      copies of the repository's materials
//   assets/{spot,teapot,plane}/*.obj
//                                 one-triangle stand-ins for the real meshes,
//                                 so that loading a scene stays fast
//   assets/spot/spot_texture.png  a 2x2 stand-in (TGA bytes: stb_image reads
//                                 by content, not by name)
//
// Made on first use, removed when the process exits.
const std::filesystem::path& sandbox();

// An input written to `file` in the sandbox, removed again at the end of
// the run, so no input can see another's file.
class InputFile {
public:
    InputFile(std::filesystem::path file, const uint8_t* data, size_t size);
    ~InputFile();
    InputFile(const InputFile&) = delete;
    InputFile& operator=(const InputFile&) = delete;

    const std::filesystem::path& path() const { return path_; }

private:
    std::filesystem::path path_;
};

// Registers the build's shader plugins (shaders/*), loaded once per process,
// with `registry`: loading one copies and dlopen()s it, which would
// dominate each run.
void add_shaders(PluginRegistry& registry);

// Checks a material that loaded against its shader's schema: each
// parameter's value in the block is the material's (converted as
// material.hpp says) or else the default, numbers lie in the declared range,
// and every texture the material names is bound. (material_yaml.cpp)
void check_bound(const Material& material);

}  // namespace facet::fuzz
