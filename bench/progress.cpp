#include "progress.hpp"

#include <sys/ioctl.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>

namespace facet::bench {

Progress::Progress(std::string what, int total, std::FILE* out)
    : what_(std::move(what)), total_(std::max(1, total)), out_(out),
      terminal_(isatty(fileno(out)) == 1) {}

double Progress::elapsed_seconds() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

std::string Progress::duration(double seconds) {
    const long s = std::lround(std::max(0.0, seconds));
    char text[32];
    if (s >= 3600) std::snprintf(text, sizeof text, "%ldh%02ldm", s / 3600, s / 60 % 60);
    else if (s >= 60) std::snprintf(text, sizeof text, "%ldm%02lds", s / 60, s % 60);
    else std::snprintf(text, sizeof text, "%lds", s);
    return text;
}

void Progress::begin(const std::string& label, std::optional<double> seconds_left) {
    const int n = std::min(done_ + 1, total_);
    if (!seconds_left && done_ > 0) seconds_left = elapsed_seconds() / done_ * (total_ - done_);
    const std::string left = seconds_left ? "about " + duration(*seconds_left) + " left"
                                          : "estimating the time left";
    if (!terminal_) {
        std::fprintf(out_, "%s %d of %d, %s: %s\n", what_.c_str(), n, total_, left.c_str(),
                     label.c_str());
        std::fflush(out_);
        return;
    }
    constexpr int kWidth = 24;
    const int filled = kWidth * done_ / total_;
    std::string bar(size_t(filled), '#');
    bar.resize(kWidth, '.');
    std::string line = "[" + bar + "] " + std::to_string(n) + " of " + std::to_string(total_) +
                       " " + what_ + ", " + left + ": " + label;
    // Cut to the terminal's width: a line that wraps is not redrawn in place.
    winsize size{};
    const size_t columns = ioctl(fileno(out_), TIOCGWINSZ, &size) == 0 && size.ws_col > 1
                               ? size_t(size.ws_col) - 1
                               : 79;
    if (line.size() > columns) line.resize(columns);
    std::fprintf(out_, "\r\033[K%s", line.c_str());  // \033[K: erase to the end of the line
    std::fflush(out_);
    shown_ = true;
}

void Progress::end() { done_ = std::min(done_ + 1, total_); }

void Progress::clear() {
    if (!shown_) return;
    std::fprintf(out_, "\r\033[K");
    std::fflush(out_);
    shown_ = false;
}

}  // namespace facet::bench
