#include "base/output_file.hpp"

#include "facet/error.hpp"
#include "facet/output.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <cerrno>
#include <climits>
#include <cstring>
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
// the handler reads no path half-written.
struct PartialSlot {
    std::atomic<int> state{0};  // 0 free, 1 being written, 2 ready
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
    if (slot >= 0) g_partials[size_t(slot)].state.store(0, std::memory_order_release);
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

}  // namespace

std::vector<AbandonedPartial> abandoned_partials(const fs::path& folder) {
    std::vector<AbandonedPartial> out;
    std::error_code ec;
    for (const fs::directory_entry& e : fs::directory_iterator(folder.empty() ? "." : folder, ec)) {
        const auto parsed = parse_partial(e.path().filename().string());
        // A process that runs (this one included) may still finish its file.
        if (!parsed || parsed->second == long(getpid()) ||
            !(::kill(pid_t(parsed->second), 0) != 0 && errno == ESRCH))
            continue;
        out.push_back({e.path(), e.path().parent_path() / parsed->first});
    }
    return out;
}

void remove_partial_outputs() noexcept {
    for (PartialSlot& s : g_partials)
        if (s.state.load(std::memory_order_acquire) == 2) unlink(s.path);
}

OutputFile::OutputFile(const fs::path& path) : path_(path), target_(path) {
    if (path == "-") {
        path_ = "standard output";
        fd_ = STDOUT_FILENO;
        stream_ = true;
        return;
    }
    struct stat st {};
    const bool exists = ::stat(path.c_str(), &st) == 0;
    if (exists && S_ISDIR(st.st_mode))
        throw Error(ErrorCode::output_failed, "cannot write an image: it is a folder",
                    path.string());
    if (exists && !S_ISREG(st.st_mode)) {
        // In place; a FIFO with no reader fails (ENXIO) rather than blocks.
        fd_ = ::open(path.c_str(), O_WRONLY | O_NONBLOCK | O_CLOEXEC);
        if (fd_ < 0)
            fail(errno == ENXIO ? "cannot write an image: no process reads the FIFO"
                                : "cannot open it",
                 errno == ENXIO ? 0 : errno);
        ::fcntl(fd_, F_SETFL, ::fcntl(fd_, F_GETFL) & ~O_NONBLOCK);
        return;
    }
    // Through a link, the file it names: the link itself stays.
    std::error_code ec;
    if (fs::is_symlink(fs::symlink_status(path, ec))) target_ = fs::weakly_canonical(path, ec);
    if (ec) target_ = path;
    partial_ = target_.string() + "." + std::to_string(getpid()) + "-" +
               std::to_string(g_partial_count.fetch_add(1)) + ".part";
    fd_ = ::open(partial_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd_ < 0) {
        const int error = errno;
        partial_.clear();  // not ours to remove
        fail("cannot create it", error);
    }
    slot_ = list_partial(partial_.string());
}

OutputFile::~OutputFile() { discard(); }

void OutputFile::discard() noexcept {
    if (fd_ >= 0 && !stream_) ::close(fd_);
    fd_ = -1;
    if (!partial_.empty()) {
        unlist_partial(slot_);
        ::unlink(partial_.c_str());
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
