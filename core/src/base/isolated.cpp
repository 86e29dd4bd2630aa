#include "base/isolated.hpp"

#include "facet/memory.hpp"
#include "facet/paths.hpp"

#include <fcntl.h>
#include <poll.h>
#include <spawn.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cerrno>
#include <csignal>
#include <cstring>
#include <fstream>
#include <new>
#include <system_error>
#include <thread>

namespace facet {

namespace {

using Clock = std::chrono::steady_clock;

// The child's account, first byte first: 'K' and the output; 'E' and an
// Error; 'M' (out of memory); 'X' and the message of another exception.
void put_u32(std::string& out, uint32_t v) { out.append(reinterpret_cast<const char*>(&v), 4); }
void put_text(std::string& out, const std::string& text) {
    put_u32(out, uint32_t(text.size()));
    out.append(text);
}

class Reader {
public:
    explicit Reader(std::string_view bytes) : rest_(bytes) {}
    uint32_t u32() {
        uint32_t v = 0;
        if (rest_.size() >= 4) std::memcpy(&v, rest_.data(), 4);
        rest_.remove_prefix(std::min<size_t>(4, rest_.size()));
        return v;
    }
    std::string text() {
        const size_t n = std::min<size_t>(u32(), rest_.size());
        std::string out(rest_.substr(0, n));
        rest_.remove_prefix(n);
        return out;
    }

private:
    std::string_view rest_;
};

std::string encode(const Error& e) {
    std::string out = "E";
    put_u32(out, uint32_t(e.code()));
    put_u32(out, uint32_t(e.line()));
    put_u32(out, uint32_t(e.column()));
    put_text(out, e.file());
    put_text(out, e.detail());
    return out;
}

constexpr uint32_t kErrorCodes = 0
#define FACET_COUNT_ERROR(id, text) +1
    FACET_ERRORS(FACET_COUNT_ERROR)
#undef FACET_COUNT_ERROR
    ;

// An id past the table (an account garbled on the way) reads as an import
// failure rather than indexing past error_text()'s table.
Error decode(std::string_view bytes) {
    Reader in(bytes);
    const uint32_t id = in.u32();
    const auto code = id < kErrorCodes ? ErrorCode(id) : ErrorCode::mesh_load_failed;
    const int line = int(in.u32());
    const int column = int(in.u32());
    std::string file = in.text();
    return Error(code, in.text(), std::move(file), line, column);
}

// Bytes of address space this process has mapped (VmSize).
uint64_t mapped_bytes() {
    std::ifstream statm("/proc/self/statm");
    uint64_t pages = 0;
    statm >> pages;
    return pages * uint64_t(sysconf(_SC_PAGESIZE));
}

void write_all(int fd, std::string_view bytes) {
    while (!bytes.empty()) {
        const ssize_t n = write(fd, bytes.data(), bytes.size());
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) return;
        bytes.remove_prefix(size_t(n));
    }
}

// Keeps the last `kKept` bytes the child wrote to stderr.
constexpr size_t kKept = 4096;

void keep_tail(std::string& tail, const char* data, size_t n) {
    tail.append(data, n);
    if (tail.size() > kKept) tail.erase(0, tail.size() - kKept);
}

// The last line of `text` with a word in it (not a rule of '='s).
std::string last_line(const std::string& text) {
    size_t end = text.size();
    while (end > 0) {
        const size_t start = text.find_last_of('\n', end - 1);
        const size_t from = start == std::string::npos ? 0 : start + 1;
        std::string line = text.substr(from, end - from);
        if (!line.empty() && line.back() == '\r') line.pop_back();
        if (std::any_of(line.begin(), line.end(), [](char c) { return std::isalpha(uint8_t(c)); }))
            return line;
        if (start == std::string::npos) break;
        end = start;
    }
    return {};
}

std::string describe_exit(int status, const std::string& said) {
    std::string out;
    if (WIFSIGNALED(status)) {
        const int sig = WTERMSIG(status);
        out = std::string("it ended on signal ") + std::to_string(sig) + " (" + strsignal(sig) + ")";
    } else {
        out = "it exited with status " + std::to_string(WEXITSTATUS(status)) +
              " before giving a result";
    }
    const std::string line = last_line(said);
    if (!line.empty()) out += "; it said: " + line;
    return out;
}

// Set in facet-sandbox once it serves its job.
bool g_in_sandbox = false;

}  // namespace

bool in_sandbox() { return g_in_sandbox; }

std::optional<std::filesystem::path> sandbox_program() {
    const std::filesystem::path program =
        (install_root() / "libexec" / "facet-sandbox").lexically_normal();
    if (access(program.c_str(), X_OK) != 0) return std::nullopt;
    return program;
}

namespace {
std::atomic<uint64_t> g_address_space_cap{0};  // address_space_cap()
}  // namespace

uint64_t address_space_cap() { return g_address_space_cap.load(std::memory_order_relaxed); }

uint64_t limit_address_space(uint64_t memory) {
    rlimit limit{};
    getrlimit(RLIMIT_AS, &limit);
    const uint64_t mapped = mapped_bytes();
    const uint64_t wanted = memory > ~uint64_t(0) - mapped ? ~uint64_t(0) : mapped + memory;
    limit.rlim_cur = std::min<rlim_t>(rlim_t(wanted), limit.rlim_max);
    const uint64_t cap = setrlimit(RLIMIT_AS, &limit) == 0 ? uint64_t(limit.rlim_cur) : 0;
    g_address_space_cap.store(cap, std::memory_order_relaxed);
    return cap;
}

int serve_sandboxed(const std::function<std::string()>& work, uint64_t memory) {
    prctl(PR_SET_PDEATHSIG, SIGKILL);
    // The account has stdout to itself: whatever else writes there (a
    // logger, a plugin) goes to stderr.
    const int account_fd = dup(STDOUT_FILENO);
    dup2(STDERR_FILENO, STDOUT_FILENO);
    if (memory) {
        limit_address_space(memory);
        // The hard limit too: plugin code in here cannot lift it.
        rlimit limit{};
        getrlimit(RLIMIT_AS, &limit);
        limit.rlim_max = limit.rlim_cur;
        setrlimit(RLIMIT_AS, &limit);
    }
    g_in_sandbox = true;
    std::string account;
    try {
        const std::string output = work();
        account.reserve(output.size() + 1);
        account.push_back('K');
        account.append(output);
    } catch (const Error& e) {
        account = encode(e);
    } catch (const std::bad_alloc&) {
        account = "M";
    } catch (const std::exception& e) {
        account = std::string("X") + e.what();
    } catch (...) {
        account = "Xan exception that is not a std::exception";
    }
    write_all(account_fd, account);
    close(account_fd);
    return 0;
}

namespace {

// Starts facet-sandbox with argv, its stdin /dev/null, its stdout and
// stderr the write ends of two pipes whose read ends it gives.
pid_t spawn_sandbox(std::vector<char*>& argv, int& result_fd, int& stderr_fd) {
    int result_pipe[2], stderr_pipe[2];
    if (pipe2(result_pipe, O_CLOEXEC) != 0)
        throw std::system_error(errno, std::generic_category(), "pipe");
    if (pipe2(stderr_pipe, O_CLOEXEC) != 0) {
        close(result_pipe[0]);
        close(result_pipe[1]);
        throw std::system_error(errno, std::generic_category(), "pipe");
    }
    posix_spawn_file_actions_t files;
    posix_spawn_file_actions_init(&files);
    posix_spawn_file_actions_addopen(&files, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
    posix_spawn_file_actions_adddup2(&files, result_pipe[1], STDOUT_FILENO);
    posix_spawn_file_actions_adddup2(&files, stderr_pipe[1], STDERR_FILENO);
    // The signals a program's interrupt handling blocks (facet::Interrupts)
    // act again, by default. The sandbox leads a process group of its own,
    // so that what it forks (plugin code may) is killed with it; it ends
    // with its parent all the same (PR_SET_PDEATHSIG).
    posix_spawnattr_t attributes;
    posix_spawnattr_init(&attributes);
    sigset_t none, defaults;
    sigemptyset(&none);
    sigemptyset(&defaults);
    for (const int sig : {SIGINT, SIGTERM, SIGHUP, SIGPIPE, SIGXFSZ}) sigaddset(&defaults, sig);
    posix_spawnattr_setsigmask(&attributes, &none);
    posix_spawnattr_setsigdefault(&attributes, &defaults);
    posix_spawnattr_setpgroup(&attributes, 0);
    posix_spawnattr_setflags(&attributes,
                             POSIX_SPAWN_SETSIGMASK | POSIX_SPAWN_SETSIGDEF | POSIX_SPAWN_SETPGROUP);
    pid_t child = -1;
    const int spawned =
        posix_spawn(&child, argv[0], &files, &attributes, argv.data(), environ);
    posix_spawn_file_actions_destroy(&files);
    posix_spawnattr_destroy(&attributes);
    close(result_pipe[1]);
    close(stderr_pipe[1]);
    if (spawned != 0) {
        close(result_pipe[0]);
        close(stderr_pipe[0]);
        throw std::system_error(spawned, std::generic_category(), "posix_spawn facet-sandbox");
    }
    result_fd = result_pipe[0];
    stderr_fd = stderr_pipe[0];
    return child;
}

// Milliseconds left until `deadline` (0 when past it), or -1, no limit.
int left_ms(bool timed, Clock::time_point deadline) {
    if (!timed) return -1;
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now());
    return int(std::clamp<int64_t>(left.count(), 0, 1 << 30));
}

// Whether `child` has exited (not reaped yet).
bool exited(pid_t child) {
    siginfo_t info{};
    return waitid(P_PID, id_t(child), &info, WEXITED | WNOHANG | WNOWAIT) == 0 &&
           info.si_pid == child;
}

// Reads both pipes until the child closes them or exits (a process it
// forked may hold them open), or time is up, and closes them; true when
// time ran out.
bool read_pipes(pid_t child, int result_fd, int stderr_fd, bool timed,
                Clock::time_point deadline, std::string& account, std::string& said) {
    pollfd fds[2] = {{result_fd, POLLIN, 0}, {stderr_fd, POLLIN, 0}};
    bool out_of_time = false, gone = false;
    while (fds[0].fd >= 0 || fds[1].fd >= 0) {
        const int left = left_ms(timed, deadline);
        if (timed && left == 0) {
            out_of_time = true;
            break;
        }
        gone = gone || exited(child);
        const int ready = poll(fds, 2, gone ? 0 : left < 0 ? 100 : std::min(left, 100));
        if (ready < 0 && errno == EINTR) continue;
        if (ready < 0 || (ready == 0 && gone)) break;  // exited, and all it wrote is read
        for (pollfd& p : fds) {
            if (p.fd < 0 || !(p.revents & (POLLIN | POLLHUP | POLLERR))) continue;
            char buffer[65536];
            const ssize_t n = read(p.fd, buffer, sizeof buffer);
            if (n < 0 && errno == EINTR) continue;
            if (n <= 0) {
                close(p.fd);
                p.fd = -1;
            } else if (&p == &fds[0]) {
                account.append(buffer, size_t(n));
            } else {
                keep_tail(said, buffer, size_t(n));
            }
        }
    }
    for (pollfd& p : fds)
        if (p.fd >= 0) close(p.fd);
    return out_of_time;
}

// Waits for the child to be reaped (the pipes close as it exits; it may
// take a moment more), killing it once time is up; its wait status.
int reap(pid_t child, bool timed, Clock::time_point deadline, bool& out_of_time) {
    if (out_of_time) kill(child, SIGKILL);
    int status = 0;
    for (;;) {
        const pid_t done = waitpid(child, &status, WNOHANG);
        if (done == child) break;
        if (done < 0 && errno != EINTR) break;
        if (!out_of_time && timed && left_ms(timed, deadline) == 0) {
            out_of_time = true;
            kill(child, SIGKILL);
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    return status;
}

// What a sandbox that exited cleanly wrote to its account (serve_sandboxed).
IsolatedResult read_account(const std::string& account) {
    IsolatedResult result;
    const std::string_view body = std::string_view(account).substr(1);
    switch (account[0]) {
        case 'K':
            result.output = std::string(body);
            break;
        case 'E':
            result.end = IsolatedResult::End::error;
            result.error = decode(body);
            result.output = result.error->what();
            break;
        case 'M':
            result.end = IsolatedResult::End::out_of_memory;
            result.output = "it ran out of memory";
            break;
        default:
            result.end = IsolatedResult::End::crashed;
            result.output = "it threw " + std::string(body);
    }
    return result;
}

}  // namespace

IsolatedResult run_sandboxed(const std::string& job, const std::vector<std::string>& args,
                             const IsolationLimits& limits) {
    const std::optional<std::filesystem::path> program = sandbox_program();
    if (!program) throw std::system_error(ENOENT, std::generic_category(), "facet-sandbox");
    std::vector<std::string> words = {program->string(), job, std::to_string(limits.memory)};
    words.insert(words.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (std::string& w : words) argv.push_back(w.data());
    argv.push_back(nullptr);
    int result_fd = -1, stderr_fd = -1;
    const pid_t child = spawn_sandbox(argv, result_fd, stderr_fd);

    const bool timed = limits.time.count() > 0;
    const Clock::time_point deadline = Clock::now() + limits.time;
    std::string account, said;
    bool out_of_time = read_pipes(child, result_fd, stderr_fd, timed, deadline, account, said);
    const int status = reap(child, timed, deadline, out_of_time);
    kill(-child, SIGKILL);  // what it forked, if anything still runs

    IsolatedResult result;
    if (out_of_time) {
        result.end = IsolatedResult::End::out_of_time;
        result.output = "it did not finish within " + std::to_string(limits.time.count()) + " ms";
        return result;
    }
    const bool clean = WIFEXITED(status) && WEXITSTATUS(status) == 0;
    if (!clean || account.empty()) {
        result.end = IsolatedResult::End::crashed;
        result.output = describe_exit(status, said);
        return result;
    }
    return read_account(account);
}

}  // namespace facet
