#include "base/output_file.hpp"

#include "facet/error.hpp"
#include "facet/output.hpp"

#include <spdlog/spdlog.h>

#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <cerrno>
#include <climits>
#include <cstring>
#include <fstream>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace facet {

namespace {

namespace fs = std::filesystem;

// The partial files not yet committed, for a signal handler to remove: a
// slot is claimed, its path copied, and only then marked ready, so that
// the handler reads no path half-written. The handler takes a ready slot
// for itself (3) before it reads the path, so that no writer reuses the
// slot meanwhile; a writer frees only a slot that is still ready.
struct PartialSlot {
    std::atomic<int> state{0};  // 0 free, 1 being written, 2 ready, 3 being removed
    char path[PATH_MAX];
};
std::array<PartialSlot, 64> g_partials;

int list_partial(const std::string& path) {
    if (path.size() >= PATH_MAX) return -1;
    for (size_t i = 0; i < g_partials.size(); ++i) {
        int expected = 0;
        if (!g_partials[i].state.compare_exchange_strong(expected, 1)) continue;
        std::memcpy(g_partials[i].path, path.c_str(), path.size() + 1);
        g_partials[i].state.store(2, std::memory_order_release);
        return int(i);
    }
    return -1;  // more than the list holds: removed by the destructor only
}

void unlist_partial(int slot) {
    int ready = 2;
    if (slot >= 0) g_partials[size_t(slot)].state.compare_exchange_strong(ready, 0);
}

std::atomic<unsigned> g_partial_count{0};

// "<image>.<pid>-<n>.part": the image's name and the pid, or nothing.
std::optional<std::pair<std::string, long>> parse_partial(const std::string& name) {
    static constexpr std::string_view kSuffix = ".part";
    if (!name.ends_with(kSuffix)) return std::nullopt;
    const std::string stem = name.substr(0, name.size() - kSuffix.size());
    const size_t dash = stem.rfind('-'), dot = stem.rfind('.', dash);
    if (dash == std::string::npos || dot == std::string::npos || dot == 0) return std::nullopt;
    const auto digits = [](std::string_view t) {
        return !t.empty() && t.size() < 10 &&
               t.find_first_not_of("0123456789") == std::string_view::npos;
    };
    const std::string_view pid(stem.data() + dot + 1, dash - dot - 1);
    if (!digits(pid) || !digits(std::string_view(stem).substr(dash + 1))) return std::nullopt;
    return std::make_pair(stem.substr(0, dot), std::stol(std::string(pid)));
}

// Whether process `pid` has ended: it does not exist, or it has exited and
// waits only to be reaped (a zombie, which in a container whose first
// process reaps no one stays so), so that it can never finish a file.
bool process_ended(long pid) {
    if (::kill(pid_t(pid), 0) != 0) return errno == ESRCH;
    std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
    std::string line;
    if (!std::getline(stat, line)) return false;
    const size_t close = line.rfind(')');  // the name may hold spaces and parentheses
    return close != std::string::npos && close + 2 < line.size() &&
           (line[close + 2] == 'Z' || line[close + 2] == 'X');
}

}  // namespace

std::vector<AbandonedPartial> abandoned_partials(const fs::path& folder) {
    std::vector<AbandonedPartial> out;
    std::error_code ec;
    for (const fs::directory_entry& e : fs::directory_iterator(folder.empty() ? "." : folder, ec)) {
        const auto parsed = parse_partial(e.path().filename().string());
        // A process that runs (this one included) may still finish its file.
        if (!parsed || parsed->second == long(getpid()) || !process_ended(parsed->second))
            continue;
        // Named as `folder` names them: "out.png" for the working folder.
        out.push_back({folder / e.path().filename(), folder / parsed->first});
    }
    return out;
}

size_t remove_abandoned_partials(const fs::path& image) {
    if (image == "-" || image.filename().empty()) return 0;
    size_t removed = 0;
    for (const AbandonedPartial& a : abandoned_partials(image.parent_path())) {
        std::error_code ec;
        if (a.image.filename() != image.filename() || !fs::remove(a.file, ec)) continue;
        spdlog::info("removed {}, which a stopped run left unfinished", a.file.string());
        ++removed;
    }
    return removed;
}

void remove_partial_outputs() noexcept {
    for (PartialSlot& s : g_partials) {
        int ready = 2;
        if (s.state.compare_exchange_strong(ready, 3, std::memory_order_acquire)) unlink(s.path);
    }
}

OutputFile::OutputFile(const fs::path& path) : path_(path), target_(path) {
    if (path == "-" || path == "/dev/stdout" || path == "/dev/fd/1" || path == "/proc/self/fd/1") {
        path_ = "standard output";  // whatever it is: a pipe, a terminal, a file (>>)
        fd_ = STDOUT_FILENO;
        stream_ = true;
        return;
    }
    struct stat st {};
    const bool exists = ::stat(path.c_str(), &st) == 0;
    if (exists && S_ISDIR(st.st_mode)) fail("cannot write an image: it is a folder", 0);
    if (exists && S_ISSOCK(st.st_mode)) fail("cannot write an image: it is a socket", 0);
    if (exists && !S_ISREG(st.st_mode)) {
        open_in_place();
        return;
    }
    target_ = link_target(path);
    partial_ = target_.string() + "." + std::to_string(getpid()) + "-" +
               std::to_string(g_partial_count.fetch_add(1)) + ".part";
    // Listed before it exists, so that no moment has it on disk unlisted.
    slot_ = list_partial(partial_.string());
    fd_ = ::open(partial_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd_ < 0) {
        const int error = errno;
        unlist_partial(slot_);
        slot_ = -1;
        partial_.clear();  // not ours to remove
        fail("cannot create it", error);
    }
}

// A device or a FIFO, written where it is. A FIFO with no reader fails
// (ENXIO) rather than blocks.
void OutputFile::open_in_place() {
    fd_ = ::open(path_.c_str(), O_WRONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd_ < 0 && errno == ENXIO) fail("cannot write an image: no process reads the FIFO", 0);
    if (fd_ < 0) fail("cannot open it", errno);
    const int flags = ::fcntl(fd_, F_GETFL);
    if (flags < 0 || ::fcntl(fd_, F_SETFL, flags & ~O_NONBLOCK) < 0) fail("cannot open it", errno);
}

// The file a chain of links ends at (the path itself when it is no link):
// the image replaces that file, and the links stay. A chain that loops is
// refused.
fs::path OutputFile::link_target(const fs::path& path) {
    fs::path at = path;
    std::error_code ec;
    for (int hops = 0; fs::is_symlink(fs::symlink_status(at, ec)); ++hops) {
        if (hops == 40) fail("cannot write an image: its links loop", 0);
        const fs::path next = fs::read_symlink(at, ec);
        if (ec) fail("cannot follow its link", ec.value());
        at = next.is_absolute() ? next : at.parent_path() / next;
    }
    return at.lexically_normal();
}

OutputFile::~OutputFile() { discard(); }

void OutputFile::discard() noexcept {
    if (fd_ >= 0 && !stream_) ::close(fd_);
    fd_ = -1;
    if (!partial_.empty()) {
        ::unlink(partial_.c_str());  // then unlisted: never on disk unlisted
        unlist_partial(slot_);
        partial_.clear();
    }
    slot_ = -1;
}

void OutputFile::fail(const char* doing, int error) {
    discard();
    std::string message = doing;
    if (error != 0) message += std::string(": ") + std::strerror(error);
    throw Error(ErrorCode::output_failed, message, path_.string());
}

void OutputFile::write(const void* data, size_t size) {
    const char* p = static_cast<const char*>(data);
    while (size > 0) {
        const ssize_t n = ::write(fd_, p, size);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) fail("cannot write the image", n < 0 ? errno : ENOSPC);
        p += n;
        size -= size_t(n);
    }
}

void OutputFile::commit() {
    if (partial_.empty()) {  // a stream or a device: its bytes are written
        if (!stream_ && ::close(fd_) != 0) {
            const int error = errno;
            fd_ = -1;
            fail("cannot finish the image", error);
        }
        fd_ = -1;
        return;
    }
    // On disk before the rename, so that a crash after it finds the new
    // bytes, not an empty file, under the name.
    if (::fsync(fd_) != 0 && errno != EINVAL) fail("cannot write the image to disk", errno);
    const int closed = ::close(fd_);
    fd_ = -1;
    if (closed != 0) fail("cannot finish the image", errno);
    if (::rename(partial_.c_str(), target_.c_str()) != 0) fail("cannot move it into place", errno);
    unlist_partial(slot_);
    slot_ = -1;
    partial_.clear();
}

}  // namespace facet
