#include "run_program.hpp"

#include <catch2/catch.hpp>

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <fstream>
#include <iterator>
#include <optional>
#include <thread>

namespace facet::test {

namespace fs = std::filesystem;
using namespace std::chrono_literals;

Finished run(const std::vector<std::string>& args, const fs::path& log_file, int signal,
             const std::string& marker) {
    Finished out;
    std::vector<char*> argv;  // made before the fork: the child only calls what is safe there
    for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    out.pid = fork();
    REQUIRE(out.pid >= 0);
    if (out.pid == 0) {
        const int fd = open(log_file.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        dup2(fd, STDOUT_FILENO);
        dup2(fd, STDERR_FILENO);
        // The signals as a program started from a shell has them, even when
        // these tests run in the background (SIGINT ignored) or blocked.
        for (const int sig : {SIGINT, SIGTERM, SIGHUP, SIGPIPE}) std::signal(sig, SIG_DFL);
        sigset_t none;
        sigemptyset(&none);
        sigprocmask(SIG_SETMASK, &none, nullptr);
        execv(argv[0], argv.data());
        _exit(127);
    }
    auto read_log = [&] {
        std::ifstream in(log_file);
        return std::string(std::istreambuf_iterator<char>(in), {});
    };
    const auto start = std::chrono::steady_clock::now();
    std::optional<std::chrono::steady_clock::time_point> signalled;
    for (;;) {
        if (waitpid(out.pid, &out.status, WNOHANG) == out.pid) break;
        const auto now = std::chrono::steady_clock::now();
        if (signal && !signalled && (marker.empty() || read_log().find(marker) != std::string::npos)) {
            kill(out.pid, signal);
            signalled = now;
        }
        if (now - start > 60s) {
            kill(out.pid, SIGKILL);
            waitpid(out.pid, &out.status, 0);
            FAIL("still running after 60 s: " << args[0]);
        }
        std::this_thread::sleep_for(2ms);
    }
    if (signalled)
        out.after_signal =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - *signalled).count();
    out.log = read_log();
    return out;
}

int partial_files(const fs::path& folder) {
    int n = 0;
    for (const fs::directory_entry& e : fs::directory_iterator(folder))
        n += e.path().extension() == ".part";
    return n;
}

}  // namespace facet::test
