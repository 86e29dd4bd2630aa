// Child processes for facet-bench --llvmpipe; see worker.hpp.
#include "worker.hpp"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <stdlib.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <thread>

extern char** environ;

namespace facet::bench {

namespace {

// This process's environment with LP_NUM_THREADS and GALLIUM_DRIVER set.
std::vector<std::string> child_environment(int threads) {
    std::vector<std::string> env;
    for (char** e = environ; *e; ++e) {
        const std::string entry = *e;
        if (entry.rfind("LP_NUM_THREADS=", 0) != 0 && entry.rfind("GALLIUM_DRIVER=", 0) != 0)
            env.push_back(entry);
    }
    env.push_back("LP_NUM_THREADS=" + std::to_string(threads));
    env.push_back("GALLIUM_DRIVER=llvmpipe");  // OSMesa could otherwise pick softpipe
    return env;
}

std::vector<char*> c_strings(std::vector<std::string>& strings) {
    std::vector<char*> out;
    for (std::string& s : strings) out.push_back(s.data());
    out.push_back(nullptr);
    return out;
}

// A fresh private folder (mkdtemp) for one worker's files; removed with
// everything in it when this goes out of scope, thrown exceptions included.
class TempDir {
public:
    TempDir() {
        std::string pattern =
            (std::filesystem::temp_directory_path() / "facet-bench-XXXXXX").string();
        if (!mkdtemp(pattern.data()))
            throw std::runtime_error("cannot make a temporary folder: " +
                                     std::string(std::strerror(errno)));
        path_ = pattern;
    }
    ~TempDir() {
        std::error_code ignored;
        std::filesystem::remove_all(path_, ignored);
    }
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;
    const std::filesystem::path& path() const { return path_; }

private:
    std::filesystem::path path_;
};

// "exit status 1", "killed by signal 11 (Segmentation fault)".
std::string describe(int status) {
    if (WIFEXITED(status)) return "exit status " + std::to_string(WEXITSTATUS(status));
    if (WIFSIGNALED(status))
        return "killed by signal " + std::to_string(WTERMSIG(status)) + " (" +
               strsignal(WTERMSIG(status)) + ")";
    return "wait status " + std::to_string(status);
}

// Waits for `pid` and returns its wait status; kills it and throws when it
// runs longer than `limit`. Polls, so that the wait itself can time out.
int wait_for(pid_t pid, std::chrono::seconds limit) {
    const auto deadline = std::chrono::steady_clock::now() + limit;
    int status = 0;
    for (;;) {
        const pid_t done = waitpid(pid, &status, WNOHANG);
        if (done == pid) return status;
        if (done < 0 && errno != EINTR)
            throw std::runtime_error("lost the llvmpipe worker process: " +
                                     std::string(std::strerror(errno)));
        if (std::chrono::steady_clock::now() > deadline) {
            kill(pid, SIGKILL);
            while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {}
            throw std::runtime_error("llvmpipe worker ran longer than " +
                                     std::to_string(limit.count()) + " s; killed it");
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
}

// Runs /proc/self/exe with `args` and `env`, its stdout and stderr (where
// spdlog and Mesa write) going to `output_path`; returns its wait status.
int run_self(std::vector<std::string> args, std::vector<std::string> env,
             const std::filesystem::path& output_path, std::chrono::seconds limit) {
    std::vector<char*> argv = c_strings(args), envp = c_strings(env);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, output_path.c_str(),
                                     O_WRONLY | O_CREAT | O_TRUNC, 0600);
    posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
    pid_t pid = 0;
    const int error =
        posix_spawn(&pid, "/proc/self/exe", &actions, nullptr, argv.data(), envp.data());
    posix_spawn_file_actions_destroy(&actions);
    if (error != 0)
        throw std::runtime_error("cannot start the llvmpipe worker process: " +
                                 std::string(std::strerror(error)));
    return wait_for(pid, limit);
}

// What the child wrote, without trailing blank lines.
std::string read_text(const std::filesystem::path& path) {
    std::ifstream in(path);
    std::ostringstream text;
    text << in.rdbuf();
    std::string s = text.str();
    while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.pop_back();
    return s;
}

LlvmpipeResult read_result(const std::filesystem::path& result_path,
                           const std::filesystem::path& mask_path) {
    LlvmpipeResult r;
    std::ifstream in(result_path);
    if (!(in >> r.median_ms >> r.min_ms))
        throw std::runtime_error("llvmpipe worker wrote no result");
    in.ignore(1);
    std::getline(in, r.renderer);
    if (!mask_path.empty()) {
        std::ifstream mask(mask_path, std::ios::binary);
        if (!mask) throw std::runtime_error("llvmpipe worker wrote no coverage mask");
        r.coverage.assign(std::istreambuf_iterator<char>(mask), {});
    }
    return r;
}

}  // namespace

int llvmpipe_threads(int facet_threads) { return facet_threads <= 1 ? 0 : facet_threads; }

LlvmpipeResult measure_llvmpipe(const LlvmpipeJob& job) {
    const TempDir dir;
    const std::filesystem::path result_path = dir.path() / "result.txt";
    const std::filesystem::path mask_path =
        job.coverage ? dir.path() / "coverage.mask" : std::filesystem::path();
    const std::filesystem::path output_path = dir.path() / "output.txt";
    std::vector<std::string> args = {"facet-bench",          "--llvmpipe-worker",
                                     result_path.string(),   "--scene",
                                     job.scene,              "--size",
                                     job.size,               "--shader",
                                     job.shader,             "--runs",
                                     std::to_string(job.runs), "--target",
                                     target_name(job.target)};
    if (job.coverage) args.insert(args.end(), {"--llvmpipe-coverage", mask_path.string()});
    const int status = run_self(args, child_environment(job.threads), output_path, job.timeout);
    const std::string messages = read_text(output_path);
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
        throw std::runtime_error("llvmpipe worker failed (" + describe(status) + ")" +
                                 (messages.empty() ? "" : ": " + messages));
    if (!messages.empty()) std::fprintf(stderr, "%s\n", messages.c_str());
    return read_result(result_path, mask_path);
}

LlvmpipeResult time_frames(LlvmpipeRenderer& renderer, const Scene& scene, int runs) {
    renderer.render(scene);  // warm-up: llvmpipe compiles its shader variants here
    std::vector<double> ms;
    for (int i = 0; i < std::max(1, runs); ++i) ms.push_back(renderer.render(scene));
    std::sort(ms.begin(), ms.end());
    LlvmpipeResult r;
    r.median_ms = ms[ms.size() / 2];
    r.min_ms = ms.front();
    r.renderer = renderer.renderer_name();
    return r;
}

void write_result(const LlvmpipeResult& result, const std::string& result_path,
                  const std::string& mask_path) {
    if (!mask_path.empty()) {
        std::ofstream mask(mask_path, std::ios::binary);
        mask.write(reinterpret_cast<const char*>(result.coverage.data()),
                   std::streamsize(result.coverage.size()));
        if (!mask) throw std::runtime_error("cannot write " + mask_path);
    }
    std::ofstream out(result_path);
    out.precision(17);
    out << result.median_ms << ' ' << result.min_ms << '\n' << result.renderer << '\n';
    if (!out) throw std::runtime_error("cannot write " + result_path);
}

LlvmpipeTarget parse_target(const std::string& name) {
    if (name == "rgba32f") return LlvmpipeTarget::rgba32f;
    if (name == "srgb8") return LlvmpipeTarget::srgb8;
    throw std::runtime_error("unknown llvmpipe target '" + name + "' (rgba32f or srgb8)");
}

std::string target_name(LlvmpipeTarget target) {
    return target == LlvmpipeTarget::rgba32f ? "rgba32f" : "srgb8";
}

}  // namespace facet::bench
