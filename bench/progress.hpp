// "n of N" and the time left, for facet-bench's long runs.
//
// On a terminal, a bar on stderr that the next item redraws in place (and
// that clear() removes before a table row is printed on stdout); otherwise
// (a pipe, a log file, CI) one plain line per item. Either way stdout keeps
// only the results.
#pragma once

#include <chrono>
#include <cstdio>
#include <optional>
#include <string>

namespace facet::bench {

class Progress {
public:
    // `total` items of `what` ("configurations", "settings").
    Progress(std::string what, int total, std::FILE* out = stderr);
    ~Progress() { clear(); }
    Progress(const Progress&) = delete;
    Progress& operator=(const Progress&) = delete;

    // Item `done() + 1` starts. The time left is `seconds_left` when the
    // caller knows better (items of unequal cost), else the mean time of the
    // items so far times the items left; nothing is shown before the first
    // item ends.
    void begin(const std::string& label, std::optional<double> seconds_left = std::nullopt);
    // The item ended.
    void end();
    // Removes the bar from the terminal (nothing for plain lines).
    void clear();

    int done() const { return done_; }
    int total() const { return total_; }
    double elapsed_seconds() const;

    // "1h02m", "3m05s", "42s".
    static std::string duration(double seconds);

private:
    std::string what_;
    int total_;
    int done_ = 0;
    std::FILE* out_;
    bool terminal_;
    bool shown_ = false;  // a bar is on the terminal's last line
    std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

}  // namespace facet::bench
