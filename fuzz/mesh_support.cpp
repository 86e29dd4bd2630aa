// The mesh targets' shared checks and probe fork (mesh_support.hpp).
#include "mesh_support.hpp"

#include "support.hpp"

#include "assets/glb_check.hpp"
#include "assets/off_check.hpp"
#include "assets/ply_check.hpp"
#include "base/isolated.hpp"

#include <facet/error.hpp>

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
#include <string>

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

// What the fork below may map beyond what it maps at the start: as
// facet-sandbox's memory budget does, it turns an allocation for whatever
// count a file declares (assimp's Collada reader reserves a float_array's
// `count`) into a failed allocation there. Without it that allocation would
// reach libFuzzer's malloc limit (2 GiB under scripts/fuzz), which writes an
// oom finding even from a fork. Half the limit leaves room for this
// process to repeat an import that fitted.
constexpr uint64_t kForkMemory = uint64_t(1) << 30;
// And the time it may take: under libFuzzer's 10 s per input.
constexpr int kForkSeconds = 8;

// True if importing `file` in this process would end it. Tried in a fork,
// limited to kForkMemory, with the fuzzer's and the sanitizers' crash
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
    // At most kForkSeconds, as facet-sandbox has a time limit: an import
    // still running then is ended, and counts as one that fails. (The
    // 2026-11-29 hour of gltf met a 36-byte file whose fork outlived
    // libFuzzer's 10 s once, on a loaded machine; replayed, it takes 1 s.)
    int status = 0;
    for (int waited_ms = 0;; ++waited_ms) {
        const pid_t done = waitpid(child, &status, WNOHANG);
        if (done == child) break;
        if (done < 0 && errno != EINTR) return true;
        if (waited_ms == kForkSeconds * 1000) {
            kill(child, SIGKILL);
            while (waitpid(child, &status, 0) < 0 && errno == EINTR) {
            }
            return true;
        }
        usleep(1000);
    }
    return !(WIFEXITED(status) && WEXITSTATUS(status) == 0);
}

}  // namespace

void check_mesh(const Mesh& mesh) {
    check_arrays(mesh);
    check_geometry(mesh);
}

// facet's checks of a mesh file before assimp reads it, in this process:
// what an input that ends the fork still runs here, so that a crash in
// facet's own code is a finding, not passed over with assimp's.
void preflight(const std::filesystem::path& file) {
    try {
        if (looks_like_ply(file)) check_ply(file);
        if (looks_like_off(file)) check_off(file);
        if (looks_like_glb(file)) check_glb(file);
    } catch (const Error&) {
    }
}

std::shared_ptr<const Mesh> import_checked(const std::filesystem::path& file) {
    if (import_crashes(file)) {
        preflight(file);
        return nullptr;
    }
    try {
        std::shared_ptr<const Mesh> mesh = load_mesh(file, MeshImport::in_process);
        check(mesh != nullptr, "load_mesh returned no mesh");
        return mesh;
    } catch (const Error& e) {
        check(e.code() == ErrorCode::file_not_found || e.code() == ErrorCode::not_a_file ||
                  e.code() == ErrorCode::mesh_load_failed || e.code() == ErrorCode::mesh_invalid,
              std::string("load_mesh threw an undocumented error id: ") + e.what());
    } catch (const std::exception& e) {
        unexpected("load_mesh", e);
    }
    return nullptr;
}

}  // namespace facet::fuzz
