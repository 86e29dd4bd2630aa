// Fuzz regressions: every input in tests/fuzz_regressions/<target>/ (and
// the target's seeds in fuzz/seeds/<target>/) goes through the same
// facet::fuzz::<target> function that the libFuzzer programs call
// (fuzz/fuzz.hpp), here in the normal build. Each file is a
// finding of scripts/fuzz or a hand-made nasty input, and scripts/fuzz seeds
// from them too. An input passes when the code under test handles it - a
// result or a facet::Error, with every rule the target checks holding -
// within the 10 seconds after which the fuzzers call it a hang.
//
// Each input runs in a child process, so that one that crashes or hangs
// fails on its own, and the others still run.
#include "fuzz.hpp"
#include "support.hpp"

#include <catch2/catch.hpp>

#include <poll.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

using Target = void (*)(const uint8_t*, size_t);

constexpr int kTimeoutMs = 10000;

// The target's regressions, then its hand-made seeds (fuzz/seeds/<target>/),
// which must pass as well.
std::vector<fs::path> inputs(const std::string& target) {
    std::vector<fs::path> files;
    const fs::path root(FACET_SOURCE_DIR);
    for (const fs::path& dir : {root / "tests" / "fuzz_regressions" / target,
                                root / "fuzz" / "seeds" / target}) {
        std::error_code ec;
        for (const auto& entry : fs::directory_iterator(dir, ec))
            if (entry.is_regular_file() && entry.path().extension() != ".py")
                files.push_back(entry.path());
    }
    std::sort(files.begin(), files.end());
    return files;
}

// In the child: runs the target and reports through `out` what went wrong,
// if anything. Fatal signals get their default action (not Catch's
// handler), so that the parent sees them.
[[noreturn]] void run_child(Target run, const std::string& bytes, int out) {
    for (int sig : {SIGSEGV, SIGBUS, SIGILL, SIGFPE, SIGABRT}) std::signal(sig, SIG_DFL);
    std::string failure;
    try {
        run(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size());
    } catch (const std::exception& e) {
        failure = e.what();
    }
    for (size_t done = 0; done < failure.size();) {
        const ssize_t n = write(out, failure.data() + done, failure.size() - done);
        if (n <= 0) break;
        done += size_t(n);
    }
    _exit(failure.empty() ? 0 : 1);
}

// Runs the target on `bytes` in a child process; "" if it passed, else what
// went wrong: the failure, a signal, or the time limit.
std::string replay(Target run, const std::string& bytes) {
    int pipe_fds[2];
    if (pipe(pipe_fds) != 0) return "cannot make a pipe";
    const pid_t child = fork();
    if (child < 0) return "cannot fork";
    if (child == 0) run_child(run, bytes, pipe_fds[1]);
    close(pipe_fds[1]);
    std::string failure;
    pollfd fd{pipe_fds[0], POLLIN, 0};
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(kTimeoutMs);
    bool timed_out = false;
    for (char buffer[4096];;) {  // read until the child closes its end
        const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
            deadline - std::chrono::steady_clock::now());
        const int ready = left.count() > 0 ? poll(&fd, 1, int(left.count())) : 0;
        if (ready < 0) continue;  // interrupted
        if (ready == 0) {
            timed_out = true;
            kill(child, SIGKILL);
            break;
        }
        const ssize_t n = ::read(pipe_fds[0], buffer, sizeof buffer);
        if (n <= 0) break;
        failure.append(buffer, size_t(n));
    }
    close(pipe_fds[0]);
    int status = 0;
    waitpid(child, &status, 0);
    if (timed_out) return "still running after " + std::to_string(kTimeoutMs / 1000) + " s: a hang";
    if (WIFSIGNALED(status)) return "crashed: " + std::string(strsignal(WTERMSIG(status)));
    if (!failure.empty()) return failure;
    if (WEXITSTATUS(status) != 0) return "exited with status " + std::to_string(WEXITSTATUS(status));
    return "";
}

void replay_all(const std::string& target, Target run) {
    const std::vector<fs::path> files = inputs(target);
    REQUIRE_FALSE(files.empty());
    for (const fs::path& file : files) {
        INFO(target << "/" << file.filename().string());
        CHECK(replay(run, facet::test::read_file(file)) == "");
    }
}

}  // namespace

// The scene and raster targets draw, on the path FACET_ISA picks: they run
// on each path ([pipeline], [raster]); the others' code is the same on all.
TEST_CASE("fuzz regressions: scene_yaml", "[fuzz][pipeline]") {
    replay_all("scene_yaml", facet::fuzz::scene_yaml);
}

TEST_CASE("fuzz regressions: material_yaml", "[fuzz]") {
    replay_all("material_yaml", facet::fuzz::material_yaml);
}

TEST_CASE("fuzz regressions: mesh_import", "[fuzz]") {
    replay_all("mesh_import", facet::fuzz::mesh_import);
}

TEST_CASE("fuzz regressions: raster", "[fuzz][raster]") {
    replay_all("raster", facet::fuzz::raster);
}

TEST_CASE("fuzz regressions: texture_decode", "[fuzz]") {
    replay_all("texture_decode", facet::fuzz::texture_decode);
}

TEST_CASE("fuzz regressions: gltf", "[fuzz]") {
    replay_all("gltf", facet::fuzz::gltf);
}
