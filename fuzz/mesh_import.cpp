// Fuzz target: mesh import, load_mesh() (core/src/assets/mesh.cpp: assimp, with
// core/src/assets/ply_check.cpp and off_check.cpp in front of assimp's PLY
// and OFF readers).
//
// The first byte picks the file's extension (kExtensions, by its value
// modulo 8), so one target covers the formats: 'o' makes it .obj, 'p' .ply,
// 'a' .off, 'b' .stl, 'c' .gltf, 'd' .glb, 'e' .dae, 'f' .3ds. The rest is
// the file, written to the sandbox (support.hpp). assimp chooses the reader
// by extension first, then by content, so any name can reach any reader.
// The import runs in this process (MeshImport::in_process), where libFuzzer
// sees its coverage; facet's programs run it in facet-sandbox, which
// turns the importer's crashes into errors. So an input on which assimp
// itself crashes (a null pointer in its Collada reader, say) is handled:
// each input is first imported in a fork, and one that ends the fork is
// passed over, as is one that allocates past a limit there (as the
// sandbox's memory budget refuses it). facet's own code before and after
// assimp (the PLY and OFF preflights, the flattening, the checks) runs in
// either.
//
// Checks:
//  - load_mesh() returns a mesh or throws facet::Error with one of the ids
//    mesh.hpp documents (file_not_found, mesh_load_failed, mesh_invalid);
//    any other exception is a finding;
//  - a mesh that loaded keeps mesh.hpp's invariants, checked here on their
//    own rather than through validate_mesh(): indexed triangles whose
//    indices are in range, finite positions, one unit-length normal per
//    vertex (generated where the file has none), UV and colour arrays empty
//    or one per vertex, and bounds that are exactly the positions' extent.
#include "support.hpp"

#include "base/isolated.hpp"

#include <facet/error.hpp>
#include <facet/mesh.hpp>

#if defined(__has_feature)
#if __has_feature(address_sanitizer)
#include <sanitizer/common_interface_defs.h>
#endif
#endif

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <csignal>
#include <filesystem>
#include <string>
#include <string_view>

namespace facet::fuzz {

namespace {

void check_arrays(const Mesh& m) {
    const size_t n = m.positions.size();
    check(n > 0 && !m.indices.empty() && m.indices.size() % 3 == 0,
          "a loaded mesh has no vertices, no triangles, or a partial triangle");
    check(m.normals.size() == n, "a loaded mesh lacks normals");
    check(m.uvs.empty() || m.uvs.size() == n, "a loaded mesh has a partial UV array");
    check(m.colors.empty() || m.colors.size() == n, "a loaded mesh has a partial colour array");
    for (const uint32_t i : m.indices) check(i < n, "a loaded mesh has an index out of range");
}

void check_geometry(const Mesh& m) {
    glm::vec3 lo = m.positions[0], hi = m.positions[0];
    for (const glm::vec3& p : m.positions) {
        check(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z),
              "a loaded mesh has a non-finite position");
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    check(m.bounds.min == lo && m.bounds.max == hi, "a loaded mesh's bounds are not its extent");
    for (const glm::vec3& n : m.normals)
        check(std::abs(glm::length(n) - 1.0f) < 1e-3f, "a loaded mesh has a non-unit normal");
}

// The extension each first byte picks, by its value modulo 8: 'o' (111)
// is .obj and 'p' (112) .ply, as when the target knew only those two; the
// others are the formats assimp reads that facet's seeds cover.
constexpr const char* kExtensions[8] = {".ply", ".off", ".stl", ".gltf", ".glb", ".dae", ".3ds",
                                        ".obj"};

// What the fork below may map beyond what it maps at the start: as
// facet-sandbox's memory budget does, it turns an allocation for whatever
// count a file declares (assimp's Collada reader reserves a float_array's
// `count`) into a failed allocation there. Without it that allocation would
// reach libFuzzer's malloc limit (2 GiB under scripts/fuzz), which writes an
// oom finding even from a fork. Half the limit leaves room for this
// process to repeat an import that fitted.
constexpr uint64_t kForkMemory = uint64_t(1) << 30;

// True if importing `file` in this process would end it: a crash or an
// abort (or a sanitizer's report) inside assimp, or an allocation past
// kForkMemory. Tried in a fork, with the fuzzer's and the sanitizers' crash
// reporting off and stderr silenced, so that its end is not taken for a
// finding. The fuzz programs have one thread, so the fork holds no lock
// another thread took.
bool import_crashes(const std::filesystem::path& file) {
    const pid_t child = fork();
    if (child < 0) return false;
    if (child == 0) {
#if defined(__has_feature)
#if __has_feature(address_sanitizer)
        __sanitizer_set_death_callback(nullptr);
#endif
#endif
        struct sigaction plain {};
        plain.sa_handler = SIG_DFL;
        for (const int sig : {SIGSEGV, SIGBUS, SIGILL, SIGFPE, SIGABRT}) sigaction(sig, &plain, nullptr);
        if (const int null = open("/dev/null", O_WRONLY); null >= 0) dup2(null, STDERR_FILENO);
        limit_address_space(kForkMemory);
        try {
            load_mesh(file, MeshImport::in_process);
        } catch (...) {
        }
        _exit(0);
    }
    int status = 0;
    while (waitpid(child, &status, 0) < 0 && errno == EINTR) {
    }
    return !(WIFEXITED(status) && WEXITSTATUS(status) == 0);
}

}  // namespace

void mesh_import(const uint8_t* data, size_t size) {
    if (size == 0) return;
    const char* extension = kExtensions[data[0] % 8];
    const InputFile input(sandbox() / "meshes" / (std::string("input") + extension), data + 1,
                          size - 1);
    if (import_crashes(input.path())) return;  // facet-sandbox's to contain
    std::shared_ptr<const Mesh> mesh;
    try {
        mesh = load_mesh(input.path(), MeshImport::in_process);
    } catch (const Error& e) {
        check(e.code() == ErrorCode::file_not_found || e.code() == ErrorCode::not_a_file ||
                  e.code() == ErrorCode::mesh_load_failed || e.code() == ErrorCode::mesh_invalid,
              std::string("load_mesh threw an undocumented error id: ") + e.what());
        return;
    } catch (const std::exception& e) {
        unexpected("load_mesh", e);
    }
    check(mesh != nullptr, "load_mesh returned no mesh");
    check_arrays(*mesh);
    check_geometry(*mesh);
}

}  // namespace facet::fuzz
