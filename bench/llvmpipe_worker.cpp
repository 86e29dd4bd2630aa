// Child processes for facet-bench --llvmpipe; see llvmpipe_worker.hpp.
#include "llvmpipe_worker.hpp"

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <atomic>
#include <filesystem>
#include <fstream>
#include <stdexcept>

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

// Runs /proc/self/exe with `args` and `env`; returns its exit status.
int run_self(std::vector<std::string> args, std::vector<std::string> env) {
    std::vector<char*> argv = c_strings(args), envp = c_strings(env);
    pid_t pid = 0;
    if (posix_spawn(&pid, "/proc/self/exe", nullptr, nullptr, argv.data(), envp.data()) != 0)
        throw std::runtime_error("cannot start the llvmpipe worker process");
    int status = 0;
    while (waitpid(pid, &status, 0) < 0)
        if (errno != EINTR) throw std::runtime_error("lost the llvmpipe worker process");
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

// A fresh path in the temporary folder for this process's files.
std::filesystem::path temp_path(const char* suffix) {
    static std::atomic<int> counter{0};
    return std::filesystem::temp_directory_path() /
           ("facet-bench-" + std::to_string(getpid()) + "-" + std::to_string(counter++) + suffix);
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
        r.coverage.assign(std::istreambuf_iterator<char>(mask), {});
    }
    return r;
}

}  // namespace

int llvmpipe_threads(int facet_threads) { return facet_threads <= 1 ? 0 : facet_threads; }

LlvmpipeResult measure_llvmpipe(const LlvmpipeJob& job) {
    const std::filesystem::path result_path = temp_path(".txt");
    const std::filesystem::path mask_path = job.coverage ? temp_path(".mask") : "";
    std::vector<std::string> args = {"facet-bench",          "--llvmpipe-worker",
                                     result_path.string(),   "--scene",
                                     job.scene,              "--size",
                                     job.size,               "--shader",
                                     job.shader,             "--runs",
                                     std::to_string(job.runs), "--llvmpipe-target",
                                     target_name(job.target)};
    if (job.coverage) args.insert(args.end(), {"--llvmpipe-coverage", mask_path.string()});
    const int status = run_self(args, child_environment(job.threads));
    LlvmpipeResult r;
    if (status == 0) r = read_result(result_path, mask_path);
    std::filesystem::remove(result_path);
    if (!mask_path.empty()) std::filesystem::remove(mask_path);
    if (status != 0)
        throw std::runtime_error("llvmpipe worker failed (exit status " + std::to_string(status) +
                                 ")");
    return r;
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
