#include "support.hpp"

#include <facet/error.hpp>

#include <cxxabi.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <typeinfo>
#include <vector>

namespace facet::fuzz {

namespace fs = std::filesystem;

namespace {

constexpr char kTriangleObj[] =
    "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nvn 0 0 1\nf 1/1/1 2/2/1 3/3/1\n";

// A 2x2 uncompressed 32-bit TGA: 18-byte header, then BGRA texels.
std::string tga_2x2() {
    std::string header(18, '\0');
    header[2] = 2;        // uncompressed true colour
    header[12] = 2;       // width
    header[14] = 2;       // height
    header[16] = 32;      // bits per pixel
    header[17] = 0x28;    // 8 alpha bits, top-left origin
    return header + std::string("\x10\x20\x30\xff\x40\x50\x60\xff\x70\x80\x90\xff\xa0\xb0\xc0\x80", 16);
}

void write_file(const fs::path& file, const std::string& bytes) {
    fs::create_directories(file.parent_path());
    std::ofstream(file, std::ios::binary) << bytes;
}

struct Sandbox {
    fs::path root;

    Sandbox() {
        root = fs::temp_directory_path() / ("facet-fuzz-" + std::to_string(getpid()));
        fs::remove_all(root);  // left by an earlier process with this pid
        const fs::path materials = root / "configs" / "materials";
        fs::create_directories(materials);
        for (const auto& entry :
             fs::directory_iterator(fs::path(FACET_SOURCE_DIR) / "configs" / "materials"))
            if (entry.path().extension() == ".yaml")
                fs::copy_file(entry.path(), materials / entry.path().filename());
        for (const char* mesh : {"spot/spot.obj", "teapot/teapot.obj", "plane/plane.obj"})
            write_file(root / "assets" / mesh, kTriangleObj);
        write_file(root / "assets" / "spot" / "spot_texture.png", tga_2x2());
    }
    ~Sandbox() {
        std::error_code ec;
        fs::remove_all(root, ec);
    }
};

// The build's plugins, from its plugin folder (PluginRegistry's default
// search path), one per folder of shaders/.
const std::vector<std::shared_ptr<ShaderPlugin>>& shaders() {
    static PluginRegistry registry;  // owns the private copies; outlives the list
    static const std::vector<std::shared_ptr<ShaderPlugin>> list = [] {
        std::vector<std::shared_ptr<ShaderPlugin>> out;
        for (const auto& entry : fs::directory_iterator(fs::path(FACET_SOURCE_DIR) / "shaders")) {
            if (!entry.is_directory()) continue;
            try {
                out.push_back(registry.get(entry.path().filename().string()));
            } catch (const Error& e) {
                std::fprintf(stderr, "fuzz: shader not loaded, materials using it fail: %s\n",
                             e.what());
            }
        }
        return out;
    }();
    return list;
}

}  // namespace

void fail(const std::string& what) { throw Failure(what); }

std::string describe(const std::exception& e) {
    const char* mangled = typeid(e).name();
    int status = 0;
    std::unique_ptr<char, void (*)(void*)> name(
        abi::__cxa_demangle(mangled, nullptr, nullptr, &status), std::free);
    return std::string(status == 0 ? name.get() : mangled) + ": " + e.what();
}

void unexpected(const std::string& call, const std::exception& e) {
    fail(call + " threw " + describe(e));
}

const fs::path& sandbox() {
    static const Sandbox box;
    return box.root;
}

InputFile::InputFile(fs::path file, const uint8_t* data, size_t size) : path_(std::move(file)) {
    fs::create_directories(path_.parent_path());
    std::ofstream out(path_, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), std::streamsize(size));
    check(bool(out), "cannot write the input to " + path_.string());
}

InputFile::~InputFile() {
    std::error_code ec;
    fs::remove(path_, ec);
}

void add_shaders(PluginRegistry& registry) {
    for (const auto& plugin : shaders()) registry.add(plugin);
}

}  // namespace facet::fuzz
